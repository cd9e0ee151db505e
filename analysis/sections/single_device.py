"""Report section for the paper's single-GPU figure: element-interaction time against elements, per backend."""
from .common import Part, md_table, plt, register

CSV = "single_device/single_device.csv"
GPU = "gpu/single_device/single_device.csv"
# The paper's L40S points (Sec. V-B): elements -> seconds per 1000 iterations; serial "roughly 2 hours" at 1.6e5.
PAPER = {"serial": [(1.6e5, 7200.0)], "opencl-allpairs": [(1.6e5, 14.1), (6.3e6, 2355.0)],
         "opencl-binned": [(1.6e5, 7.2), (6.3e6, 255.0)]}
PAPER_LINE = ("1 NVIDIA L40S (serial on a Xeon Gold 6348), mechanics only, per 1000 iterations: at 1.6e5 elements "
              "serial ~2 h, GPU all-pairs 14.1 s, GPU binned 7.2 s; at 6.3e6 binned 255 s, all-pairs 2,355 s (9.2x); "
              "40x more elements cost binned 35x more time; below 1e3 elements the two GPU codes are comparable.")


def timed(rows):
    return [r for r in rows if r.get("seconds")]


def device_of(rows, backend):
    """The device a backend's rows ran on ('NVIDIA CUDA: NVIDIA H200', 'Portable Computing Language: cpu'; the host
    CPU for serial and cpu-binned)."""
    devs = {r.get("device", "") for r in timed(rows) if r["backend"] == backend and r.get("device")}
    if backend in ("serial", "cpu-binned"):
        return "host CPU"
    return ", ".join(sorted(devs)) or "?"


def label(rows, backend):
    dev = device_of(rows, backend)
    if backend.startswith("opencl") and ("Portable" in dev or "pocl" in dev.lower() or "cpu" in dev.lower()):
        return f"{backend} (PoCL on the CPU)"
    if backend.startswith("opencl") and "NVIDIA" in dev:
        return f"{backend} ({dev.split(':')[-1].strip()})"
    return f"{backend} ({dev})"


def table(rows, title):
    out = [f"# {title}", "",
           "Mechanics only; seconds per 1000 iterations (measured over `steps` iterations and scaled), element-steps "
           "per second, and the density of the tissue: elements per cutoff cube around an element, candidates in "
           "its 27-bin stencil and neighbours within the cutoff.", "",
           md_table(["backend", "device", "precision", "elements", "s / 1000 it.", "element-steps/s", "per cutoff cube",
                     "candidates", "within cutoff"],
                    [(r["backend"], device_of(rows, r["backend"]), r["precision"], r["elements"],
                      f"{float(r['s_per_1000_steps']):.3g}", f"{float(r['element_steps_per_s']):.3g}",
                      f"{float(r['per_cutoff_cube']):.1f}", f"{float(r['candidates']):.0f}",
                      f"{float(r['neighbours']):.0f}") for r in timed(rows)], align="lllrrrrrr")]
    skipped = sorted({r["backend"] for r in rows if not r.get("seconds")})
    if skipped:
        out += ["", "Not run above their `max_cells` (too slow on this profile): " + ", ".join(skipped) + "."]
    return "\n".join(out) + "\n"


def figure(sets, with_paper=True):
    """Log-log time per 1000 iterations against elements: one line per (run, backend), the device in the label,
    the paper's L40S points as open markers, O(n) and O(n^2) reference slopes."""
    p = plt()
    fig, ax = p.subplots(figsize=(7.5, 5))
    colours = {"serial": "tab:red", "cpu-binned": "tab:purple", "opencl-allpairs": "tab:orange",
               "opencl-binned": "tab:blue"}
    styles = ["o-", "s--", "^:"]
    allpts = []
    for k, (name, rows) in enumerate(sets):
        for b in sorted({r["backend"] for r in rows}):
            pts = sorted((int(r["elements"]), float(r["s_per_1000_steps"])) for r in timed(rows) if r["backend"] == b)
            if pts:
                ax.loglog([q[0] for q in pts], [q[1] for q in pts], styles[k % 3], color=colours.get(b, "k"), ms=5,
                          label=f"{name}: {label(rows, b)}")
                allpts += pts
    if with_paper:
        for b, pts in PAPER.items():
            ax.loglog([q[0] for q in pts], [q[1] for q in pts], "D", mfc="none", ms=9, mew=1.5,
                      color=colours[b], label=f"paper, L40S: {b}" if b != "serial" else "paper: serial (Xeon 6348)")
            allpts += pts
    if allpts:
        x0 = min(q[0] for q in allpts)
        x1 = max(q[0] for q in allpts)
        y0 = min(q[1] for q in allpts if q[0] == x0)
        ax.loglog([x0, x1], [y0, y0 * x1 / x0], "k:", lw=1, label="O(n)")
        ax.loglog([x0, x1 / 10], [y0, y0 * (x1 / 10 / x0) ** 2], "k--", lw=1, label="O(n$^2$)")
    ax.set_xlabel("subcellular elements")
    ax.set_ylabel("seconds per 1000 iterations (mechanics)")
    ax.set_title("Single device: element-interaction time (log-log)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    return fig


def near(rows, backend, elements):
    """s per 1000 iterations of the backend's row nearest in elements (log distance), or None."""
    import math
    pts = [(abs(math.log(int(r["elements"]) / elements)), float(r["s_per_1000_steps"]), int(r["elements"]))
           for r in timed(rows) if r["backend"] == backend]
    return min(pts)[1:] if pts else None


def build(ctx):
    small, gpu = ctx.rows(CSV), ctx.committed_rows(GPU)
    runs = []
    sets = []
    if small:
        steps = small[0].get("steps", "?")
        runs.append(("This run", ctx.cpu_run(CSV, "1", 1, "-", f"{steps} iterations, scaled to 1000"),
                     ctx.source(CSV) + "\n\n" + ctx.table("single_device", table(small, "Single-device time, this run"))))
        sets.append(("this run", small))
    card = ctx.committed_gpu(GPU) if gpu else ""
    short = card.split()[1] if len(card.split()) > 1 else card  # 'NVIDIA H100 80GB HBM3' -> 'H100'
    if gpu:
        runs.append(("Committed paper profile (GPU)",
                     f"profile **paper** · machine: 1 {card} ({device_of(gpu, 'opencl-binned')}) · ranks: 1 · "
                     f"cores: - · launches: 1 · intervals: - · {gpu[0]['steps']} iterations",
                     "From " + ctx.committed_source(GPU) + ".\n\n" +
                     ctx.table("single_device_gpu", table(gpu, f"Single-device time, one {short}"))))
        sets.append((short, gpu))
    if not sets:
        return None
    runs[-1] = runs[-1][:2] + (runs[-1][2] + "\n" + ctx.figure("single_device", figure(sets)),)
    reading = "No paper-profile data: the small profile's sizes stop far below the paper's."
    supported = None
    if gpu:
        b1, b2 = near(gpu, "opencl-binned", 1.6e5), near(gpu, "opencl-binned", 6.3e6)
        a1 = near(gpu, "opencl-allpairs", 1.6e5)
        if b1 and b2:
            ratio = b2[0] / b1[0]
            growth = b2[1] / b1[1]
            reading = (f"Agrees in shape, differs in size: binned time grows {ratio:.1f}x for {growth:.0f}x the "
                       f"elements (paper 35x for 40x), near-linear as in the paper; the {short} is "
                       f"{7.2 / b1[0]:.0f}x (1.6e5) and {255 / b2[0]:.0f}x (6.3e6) faster than the paper's L40S")
            if a1:
                reading += (f"; all-pairs at {a1[1]:,} elements takes {a1[0]:.3g} s, {a1[0] / b1[0]:.0f}x binned "
                            f"(paper 14.1 s, 2x): the paper's all-pairs is relatively much faster than ours, reason "
                            f"not known")
            reading += ". The small profile (PoCL on 2 CPU cores) shows the same O(n) / O(n^2) split at 60-6000 cells."
            supported = True
            mine = sorted((int(r["elements"]), float(r["s_per_1000_steps"])) for r in timed(small or [])
                          if r["backend"] == "cpu-binned")
            this_run = (f"cpu-binned {mine[0][1]:.3g} s -> {mine[-1][1]:.3g} s per 1000 it. for {mine[-1][0] / mine[0][0]:.0f}x "
                        f"the elements ({mine[0][0]:,} -> {mine[-1][0]:,})" if len(mine) > 1 else "")
            summary = (f"in shape (near-linear binned); {short} binned {b1[0]:.3g} s / {b2[0]:.3g} s at "
                       f"{b1[1]:.3g} / {b2[1]:.3g} elements vs L40S 7.2 s / "
                       f"255 s; growth {ratio:.0f}x for {growth:.0f}x elements (paper 35x for 40x)")
            return Part(runs, PAPER_LINE, reading, supported, summary, this_run=this_run)
    return Part(runs, PAPER_LINE, reading, supported)


register("single_device", 1, "Single-device element-interaction time against elements", build, [CSV],
         paper="fig:single_gpu", claim="L40S binned 7.2 s / 255 s per 1000 it. at 1.6e5 / 6.3e6 elements")
