"""What every report section shares: CSV reading, atomic writes, the section registry, provenance, tables, setup lines."""
import csv
import math
import os
import platform
import re
import statistics
import subprocess
from collections import OrderedDict

import numpy as np
from scipy import stats as _stats

import provenance
import semlb_names

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# The paper's figures of its evaluation section (Sec. V), in its order: (label, what the figure shows).
PAPER_FIGURES = OrderedDict([
    ("fig:single_gpu", "Single-device element-interaction time against elements"),
    ("fig:scaling", "Multi-GPU strong scaling: computation time and speedup, two sizes"),
    ("fig:rank_balance", "Per-rank computation time per interval: static, reactive, RNN (GRU)"),
    ("fig:load_balance", "End-to-end load balancing: runtime, mean imbalance, migration"),
    ("fig:rnn_prediction", "Controller evaluation on held-out scenarios: imbalance and migration"),
    ("fig:epidermal_visualization", "Epidermal development, Day 0-5: cells as ellipsoids by type"),
])

# The paper's order of the policies it compares (its Sec. V-E); names the binary lists beyond these follow by name.
PAPER_POLICY_ORDER = ["static", "persistence", "holt", "reactive", "gru", "learned_repartition", "oracle"]


class Section:
    """One section of REPORT.md: `key` (its anchor), `order` (paper figures 1-6 in the paper's order, then the
    extra experiments from 10), `title` (what it shows), `paper` (the paper label it reproduces, or None), `csvs`
    (CSV paths relative to the results folder it reads; the first is the one whose manifest copy it cites) and
    `build(ctx)` returning a Part, or None when it has nothing to show."""

    def __init__(self, key, order, title, build, csvs=(), paper=None):
        self.key, self.order, self.title, self.build, self.csvs, self.paper = key, order, title, build, list(csvs), paper


class Part:
    """A section's content: `runs` (list of (heading, setup line, markdown body)), `paper` (the paper's numbers),
    `reading` (one line: agrees / differs and why), `supported` (False when the data does not support the paper's
    claim, None when there is nothing to compare), `summary` (a few words on the committed GPU rows, or on this run
    when basis is "run"), `this_run` (a few words on what this run measured), `basis` ("gpu": the verdict is drawn
    from committed GPU rows, so stale rows withdraw it; "run": from this run; None: "gpu" when the section read
    committed GPU rows), `key_table` (the one markdown table REPORT.md shows; default: the first table of the runs)."""

    def __init__(self, runs, paper="", reading="", supported=None, summary="", this_run="", basis=None, key_table=None):
        self.runs, self.paper, self.reading, self.supported, self.summary = runs, paper, reading, supported, summary
        self.this_run, self.basis, self.key_table = this_run, basis, key_table


SECTIONS = []


def register(key, order, title, build, csvs=(), paper=None, claim=""):
    """Adds a section to the report; each module of analysis/sections/ calls this for what it shows. CLAIM: the
    paper's number in a few words, for the summary table."""
    sec = Section(key, order, title, build, csvs, paper)
    sec.claim = claim
    SECTIONS.append(sec)


def md_table(header, rows, align=None):
    """A markdown table: HEADER (column names), ROWS (sequences of cells, str() of each; None as empty), ALIGN (one
    character per column, 'l' or 'r'; default: 'r' for a column whose cells all read as numbers, else 'l')."""
    cells = [["" if c is None else str(c) for c in r] for r in rows]
    for r in cells:
        if len(r) != len(header):
            raise ValueError(f"md_table: a row of {len(r)} cells under {len(header)} columns: {r}")
    if align is None:
        def numeric(text):
            try:
                float(text.split()[0].rstrip("%x"))
                return True
            except (ValueError, IndexError):
                return text in ("", "-")
        align = "".join("r" if cells and all(numeric(r[i]) for r in cells) else "l" for i in range(len(header)))
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---:" if a == "r" else "---" for a in align) + "|"]
    out += ["|" + "|".join(f" {c} " if c else " " for c in r) + "|" for r in cells]
    return "\n".join(out)


def read_rows(path):
    """The rows of a CSV as dicts (csv.DictReader)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def atomic_write(path, text_or_fig):
    """Writes text or a matplotlib figure (PNG) to a temporary file, then renames it onto path."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = path + ".tmp"
    if isinstance(text_or_fig, str):
        with open(tmp, "w") as f:
            f.write(text_or_fig)
    else:
        text_or_fig.savefig(tmp, dpi=130, format="png")
        import matplotlib.pyplot as plt
        plt.close(text_or_fig)
    os.replace(tmp, path)


def plt():
    """matplotlib.pyplot on the Agg backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as p
    return p


def by(rows, column):
    """column value -> rows with it, in first-seen order."""
    out = OrderedDict()
    for r in rows:
        out.setdefault(r[column], []).append(r)
    return out


def mean_sd(vals):
    """(mean, sample sd; 0 for one value)."""
    return statistics.fmean(vals), (statistics.stdev(vals) if len(vals) > 1 else 0.0)


def fmean(vals):
    vals = list(vals)
    return statistics.fmean(vals) if vals else float("nan")


def t_interval(diffs):
    """Mean and 95% t-interval half-width of paired differences (Student t quantile from scipy.stats; n >= 2;
    half-width inf for n = 1)."""
    d = np.asarray(diffs, dtype=float)
    m = float(d.mean())
    if d.size < 2:
        return m, math.inf
    return m, float(_stats.t.ppf(0.975, d.size - 1) * d.std(ddof=1) / math.sqrt(d.size))


def order_policies(names):
    """Policy names in the paper's order, then the others by name."""
    return sorted(set(names), key=lambda p: (PAPER_POLICY_ORDER.index(p) if p in PAPER_POLICY_ORDER else 99, p))


def this_machine():
    """'CPU model, N cores' of the machine running the report (where `make experiments` made the small profile)."""
    model = platform.processor() or "CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} cores"


def setup(profile, machine, ranks="1", cores=None, launches=1, intervals="-", extra=""):
    """The one line each result states: profile, machine, ranks, cores, launches and intervals."""
    cores = cores if cores is not None else os.cpu_count()
    line = (f"profile **{profile}** · machine: {machine} · ranks: {ranks} · cores: {cores} · launches: {launches} · "
            f"intervals: {intervals}")
    return line + (f" · {extra}" if extra else "")


def committed_date(path):
    """The date (YYYY-MM-DD) of the last commit of a repository file, or 'uncommitted'."""
    try:
        out = subprocess.run(["git", "-C", REPO, "log", "-1", "--format=%cs", "--", os.path.relpath(path, REPO)],
                             capture_output=True, text=True, timeout=20).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        out = ""
    return out or "uncommitted"


def gpu_machines():
    """Machine letter -> number of H200s, from results/gpu/machines.txt (the letters of the GPU CSVs)."""
    out = {}
    path = os.path.join(REPO, "results", "gpu", "machines.txt")
    if os.path.exists(path):
        for line in open(path):
            m = re.match(r"^([A-Z]) GPU \d+: (.*) \(UUID", line)
            if m:
                out[m.group(1)] = out.get(m.group(1), 0) + 1
    return out


class Context:
    """What a section's build sees: the results folder, the committed results, the binary's registries and the
    writers of tables and figures (each write is recorded for the report)."""

    def __init__(self, results, committed, semlb):
        self.results, self.committed, self.semlb = results, committed, semlb
        self.written = []
        self.used_committed = []  # committed results the current section read (report.py resets it per section)
        self._names = {}

    def path(self, rel):
        return os.path.join(self.results, rel)

    def rows(self, rel):
        """The rows of RESULTS/rel, or None when the file is absent or empty."""
        p = self.path(rel)
        if not os.path.exists(p):
            return None
        rows = read_rows(p)
        return rows or None

    def committed_rows(self, rel):
        """The rows of a committed CSV (rel to the repository's results/), or None; remembered as used by the
        section being built (its provenance decides whether the section may draw a verdict from it)."""
        p = os.path.join(self.committed, rel)
        if not os.path.exists(p):
            return None
        if rel not in self.used_committed:
            self.used_committed.append(rel)
        return read_rows(p)

    def committed_provenance(self, rel):
        """provenance.describe of a committed file (commit, date, status fresh/stale/unknown, milestones before)."""
        return provenance.describe(os.path.join(self.committed, rel))

    def committed_gpu(self, rel):
        """The card a committed result ran on, from its provenance record's `device` ('NVIDIA H100 80GB HBM3, 580.159.04'
        -> 'NVIDIA H100 80GB HBM3'); 'NVIDIA H200' for the records made before `device` was recorded (every GPU result
        until 2026-12-03 came from H200s)."""
        rec = provenance.record(os.path.join(self.committed, rel)) or {}
        return rec.get("device", "").split(",")[0].strip() or "NVIDIA H200"

    def committed_source(self, rel):
        """'`results/rel` (made with semlb abc1234, DATE · **stale** ... )' for a committed file."""
        return f"`results/{rel}` ({provenance.label(os.path.join(self.committed, rel))})"

    def table(self, name, text):
        """Writes RESULTS/tables/NAME.md; returns its body for inlining (its '# ' title made a '####' heading)."""
        rel = f"tables/{name}.md"
        atomic_write(self.path(rel), text)
        self.written.append(rel)
        print(f"report: wrote {self.path(rel)}")
        return text.replace("\n# ", "\n#### ").removeprefix("# ").split("\n", 1)[-1].strip() + "\n"

    def figure(self, name, fig):
        """Writes RESULTS/figures/NAME.png; returns the markdown image line."""
        rel = f"figures/{name}.png"
        atomic_write(self.path(rel), fig)
        self.written.append(rel)
        print(f"report: wrote {self.path(rel)}")
        return f"![{rel}]({rel})\n"

    def provenance(self, rel):
        """(profile, command, revision) from the sweep's manifest copy beside RESULTS/rel, or Nones."""
        p = os.path.splitext(self.path(rel))[0] + ".manifest.yaml"
        if not os.path.exists(p):
            return None, None, None
        lines = open(p).read().splitlines()
        command = lines[0].lstrip("# ").strip() if lines else ""
        profile = command.split("--profile ")[1].split()[0] if "--profile " in command else "?"
        rev = next((l.split(":", 1)[1].strip() for l in lines[:4] if l.startswith("# git revision:")), "?")
        rev = rev if "git" in rev else f"git {rev}"
        return profile, command, rev

    def manifest_setting(self, rel, key, default=None):
        """A `set:` value of the profile the sweep ran (the manifest copy beside RESULTS/rel): the profile's
        `set:` first, then the manifest's; `default` when absent or unreadable."""
        p = os.path.splitext(self.path(rel))[0] + ".manifest.yaml"
        profile = self.provenance(rel)[0]
        if not os.path.exists(p):
            return default
        try:
            import yaml  # python3-yaml; only the manifest copy's settings need it
            doc = yaml.safe_load(open(p)) or {}
        except Exception:  # noqa: BLE001 - no yaml module or a copy it cannot read: the default
            return default
        prof = ((doc.get("profiles") or {}).get(profile) or {})
        for block in ((prof.get("set") or {}), (prof.get("axes") or {}), (doc.get("set") or {}), (doc.get("axes") or {})):
            if key in block:
                return block[key]
        if key == "launches":
            return prof.get("launches", doc.get("launches", default))
        return default

    def names(self, kind):
        """The names the binary registers for KIND (semlb_names.names: any kind of semlb_names.kinds, e.g. policies,
        engine-policies, effects, backends, cell-types), asked once per kind; semlb_names.NamesError (one line) when the
        binary cannot list them."""
        if kind not in self._names:
            self._names[kind] = semlb_names.names(self.semlb, kind)
        return self._names[kind]

    def cpu_run(self, rel, ranks="1", launches=1, intervals="-", extra="", what="CPU backends, OpenCL on PoCL"):
        """The setup line of a run under RESULTS/rel: its profile (manifest copy; small without one), this machine
        and what ran on it."""
        profile = self.provenance(rel)[0] or "small"
        return setup(profile, f"this machine ({this_machine()}; {what})", ranks, os.cpu_count(), launches, intervals,
                     extra)

    def source(self, rel):
        """'From `RESULTS/rel` (`command`, revision R)'."""
        _, command, rev = self.provenance(rel)
        return f"From `{rel}`" + (f" (`{command}`, {rev})" if command else "") + "."
