"""The report's sections: one module per experiment, each calling common.register; report.py imports them all."""
