#!/usr/bin/env python3
"""REPORT.md as the paper's evaluation section, in two levels, with tables (markdown) and figures (PNG) from results/.

Each module of analysis/sections/ registers the sections it makes (common.register: the CSVs it reads, its tables and
figures, the paper's numbers and a one-line reading); this script imports every module there, builds each section
and writes RESULTS/REPORT.md (at most 400 lines: the summary table, which controller to run, and per section its
figure, its key table and a link) and RESULTS/report/NN-key.md (each section in full), in the paper's order (its
figures first, then the experiments beyond them). A committed GPU result is marked stale when the engine's kernels or
the controllers changed after the commit it was made with (analysis/provenance.py), and the summary draws no verdict
from it. A new experiment is one new module file. Python csv + numpy/scipy + matplotlib, no pandas.
Policy, effect and cell-type names come from the binary (`semlb list KIND --json`); a section that needs them
stops the report with exit 2 and a one-line reason when the binary cannot list them.
Usage: report.py [--results DIR] [--semlb BINARY] [--committed DIR]"""
import argparse
import importlib
import os
import pkgutil
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import provenance  # noqa: E402
import semlb_names  # noqa: E402
from sections import common, controller_eval_engine  # noqa: E402


def load_sections():
    """Imports every module of analysis/sections/ (each registers its sections); returns them in report order."""
    import sections
    for m in sorted(pkgutil.iter_modules(sections.__path__), key=lambda m: m.name):
        if m.name != "common":
            importlib.import_module(f"sections.{m.name}")
    return sorted(common.SECTIONS, key=lambda s: (s.order, s.key))


def version(semlb):
    """`semlb --version`, or 'semlb (binary not built)'."""
    import subprocess
    try:
        out = subprocess.run([semlb, "--version"], capture_output=True, text=True, timeout=30)
        return out.stdout.strip() or "semlb (unknown version)"
    except (OSError, subprocess.SubprocessError):
        return "semlb (binary not built)"


MAX_LINES = 400  # REPORT.md's length limit (tests/analysis/test_report.sh checks it)
KEY_ROWS = 8     # data rows of a section's key table shown in REPORT.md; the rest are on its detail page


def slug(i, sec):
    """The detail page of section I: report/NN-key.md (relative to the results folder)."""
    return f"report/{i:02d}-{sec.key}.md"


def first_table(text, max_rows=KEY_ROWS):
    """The first markdown table of TEXT (header, rule and at most MAX_ROWS rows, then a line saying how many more),
    or ''."""
    lines, block = text.splitlines(), []
    for i, line in enumerate(lines):
        if line.startswith("|"):
            block.append(line)
        elif block:
            break
    if len(block) < 3:
        return ""
    more = len(block) - 2 - max_rows
    return "\n".join(block[:2 + max_rows]) + (f"\n\n({more} more rows on the detail page.)" if more > 0 else "")


def first_figure(text):
    """The first markdown image line of TEXT, or ''."""
    return next((l for l in text.splitlines() if l.startswith("![")), "")


def gpu_state(ctx, rels):
    """(worst provenance status of the committed files RELS: stale > unknown > fresh, or None without any; one phrase
    naming the commits and dates they were made with and the milestones they predate)."""
    if not rels:
        return None, ""
    ds = {rel: ctx.committed_provenance(rel) for rel in rels}
    order = [provenance.STALE, provenance.UNKNOWN, provenance.FRESH]
    worst = min((d["status"] for d in ds.values()), key=order.index)
    made = sorted({(d["commit"][:7] or "?", d["date"] or "?") for d in ds.values()})
    before = sorted({b for d in ds.values() for b in d["before"]})
    phrase = "made with " + ", ".join(f"`{c}` {d}" for c, d in made)
    if worst == provenance.STALE:
        last = next(d["detail"] for d in ds.values() if d["status"] == provenance.STALE)
        phrase += f"; **stale**: kernels or controllers changed since (last `{last}`)"
    elif worst == provenance.UNKNOWN:
        phrase += "; staleness **unknown** (" + next(d["detail"] for d in ds.values() if d["status"] == provenance.UNKNOWN) + ")"
    if before:
        phrase += "; before " + " and ".join(before)
    notes = sorted({d["note"] for d in ds.values() if d["note"]})
    if notes:
        phrase += "; " + "; ".join(notes)
    return worst, phrase


def verdict(sec, part, state):
    """The summary table's verdict of a section: none from stale or unknown GPU rows when the verdict rests on them."""
    if part is None:
        return "not run"
    basis = part.basis or ("gpu" if state else "run")
    if part.supported is None:
        return "no paper numbers" if not sec.paper else "see the reading"
    if basis == "gpu" and state != provenance.FRESH:
        return f"**no verdict**: the committed GPU rows are {state} (rerun: `make gpu-results`)"
    return "agrees" if part.supported else "**not supported**"


def detail_page(ctx, i, sec, part, state_phrase):
    """RESULTS/report/NN-key.md: every run of the section with its long tables and figures."""
    lines = [f"# {i}. {sec.title}", "", "[Back to the report](../REPORT.md)", ""]
    if sec.paper:
        lines += [f"*Paper: Fig. `{sec.paper}` ({common.PAPER_FIGURES[sec.paper]}).*", ""]
    if state_phrase:
        lines += [f"*Committed GPU rows: {state_phrase}.*", ""]
    for heading, setup_line, text in part.runs:
        lines += [f"## {heading}", "", setup_line, "", text.strip(), ""]
    if part.paper:
        lines += [f"**Paper.** {part.paper}", ""]
    if part.reading:
        lines += [f"**Reading.** {part.reading}", ""]
    text = "\n".join(lines).replace("](figures/", "](../figures/")
    common.atomic_write(ctx.path(slug(i, sec)), text + "\n")


def write_report(ctx, built, states, controller_text=""):
    """RESULTS/REPORT.md (the summary table, which controller to run, then per section its one figure, its one
    table and a link to its detail page) and RESULTS/report/NN-key.md (the sections in full)."""
    lines = ["# semlb: the paper's evaluation, reproduced", "",
             f"Generated by `analysis/report.py` from `{ctx.results}/` on {time.strftime('%Y-%m-%d')} with "
             f"{version(ctx.semlb)}. The paper: Moisseyev et al., *Scalable Multi-GPU Simulation of 3D Multicellular "
             "Growth with RNN-Based Workload Balancing* (docs/paper.md, Sec. V). **This run**: what `make experiments` "
             "measured here (the small profile unless `PROFILE=paper`). **Committed GPU**: runs on NVIDIA H200s and H100s "
             "under `results/gpu/` (each section names its card), each with the semlb commit and date it was made with "
             "(`provenance.json`); a result made "
             "before the last change to the engine's kernels or the controllers is **stale** and no verdict is drawn "
             "from it (`make gpu-results` remakes them on a GPU machine). Each section links its detail page.", ""]
    for i, (sec, part) in enumerate(built, 1):
        if part is not None:
            detail_page(ctx, i, sec, part, states[sec.key][1])
    for key_rows in (KEY_ROWS, 5, 3, 1):  # shorter key tables until REPORT.md fits its limit
        text = report_text(ctx, built, states, controller_text, lines, key_rows)
        if text.count("\n") <= MAX_LINES:
            break
    common.atomic_write(os.path.join(ctx.results, "REPORT.md"), text)
    n = text.count("\n")
    print(f"report: wrote {os.path.join(ctx.results, 'REPORT.md')} ({n} lines)"
          + (f"; over the {MAX_LINES}-line limit" if n > MAX_LINES else ""))


def report_text(ctx, built, states, controller_text, lines, key_rows):
    """REPORT.md's text after its opening LINES, with key tables of at most KEY_ROWS rows."""
    lines = list(lines)
    summary, body = [], []
    for i, (sec, part) in enumerate(built, 1):
        state, phrase = states[sec.key]
        claim = sec.claim or (f"`{sec.paper}`" if sec.paper else "beyond the paper")
        made = phrase.split(";")[0].removeprefix("made with ")
        gpu = "-" if state is None else (f"**{state}** ({made})" if state != provenance.FRESH else f"current ({made})") + (
            f": {part.summary}" if part and part.summary and part.basis != "run" else "")
        run = "not run" if part is None else (part.this_run or ("yes" if any(h.startswith("This run") for h, _, _ in part.runs)
                                                                 else "-"))
        if part is not None and part.basis == "run" and part.summary and not part.this_run:
            run = part.summary
        summary.append((i, f"[{sec.title}](#{sec.key})", claim, gpu, run, verdict(sec, part, state)))
        body += ["", f'<a id="{sec.key}"></a>', f"## {i}. {sec.title}", ""]
        if part is None:
            body += ["Not run: nothing under " + ", ".join(f"`{ctx.results}/{c}`" for c in sec.csvs)
                     + " (`make experiments` makes it).", ""]
            continue
        alltext = "\n".join(t for _, _, t in part.runs)
        body += [f"*Paper: Fig. `{sec.paper}` ({common.PAPER_FIGURES[sec.paper]}).*" if sec.paper else
                 "*Beyond the paper's figures.*", ""]
        if phrase:
            body += [f"*Committed GPU rows: {phrase}.*", ""]
        fig = first_figure(alltext)
        if fig:
            body += [fig, ""]
        table = first_table(part.key_table if part.key_table is not None else alltext, key_rows)
        if table:
            body += [table.strip(), ""]
        if part.reading:
            rests_on_stale = (part.basis or ("gpu" if state else "run")) == "gpu" and state not in (None, provenance.FRESH)
            body += [f"**Reading{' (of ' + state + ' GPU rows: no verdict drawn from it)' if rests_on_stale else ''}.** "
                     f"{part.reading}", ""]
        body += [f"Details (every run, its setup and the long tables): [{slug(i, sec)}]({slug(i, sec)})", ""]
    lines.append(common.md_table(["#", "section", "paper", "committed GPU", "this run", "verdict"], summary,
                                 align="rlllll"))
    if controller_text:
        lines += ["", "## Which controller should I run?", "", controller_text.strip()]
    return "\n".join(lines + body) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default="results", help="results directory (default: results)")
    ap.add_argument("--semlb", default=os.path.join(common.REPO, "build", "cli", "semlb"),
                    help="the binary whose registries name policies, effects and cell types")
    ap.add_argument("--committed", default=os.path.join(common.REPO, "results"),
                    help="the committed results (results/gpu, results/cpu); default: the repository's")
    args = ap.parse_args()
    ctx = common.Context(args.results, args.committed, args.semlb)
    built, states = [], {}
    for sec in load_sections():
        ctx.used_committed = []
        try:
            part = sec.build(ctx)
        except semlb_names.NamesError as e:  # a section that names what the binary registers
            print(f"report: {sec.key}: {e}", file=sys.stderr)
            return 2
        states[sec.key] = gpu_state(ctx, ctx.used_committed)
        if part is not None or sec.paper:
            built.append((sec, part))
    if not any(part for _, part in built if part is not None) or not any(
            os.path.exists(ctx.path(c)) for sec, _ in built for c in sec.csvs):
        print(f"report: no known CSV under {args.results}/ (run make experiments)", file=sys.stderr)
        return 2
    write_report(ctx, built, states, controller_eval_engine.which_controller(ctx))
    return 0


if __name__ == "__main__":
    sys.exit(main())
