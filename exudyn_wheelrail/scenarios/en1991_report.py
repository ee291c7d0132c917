"""What a checking engineer reads of an EN 1991-2 dynamic check (:mod:`.en1991_dynamic`): the envelope figure
(``envelope.png``: the deck acceleration against speed, one panel per mass bound, a line per train, each train's
resonance speeds ``v_i = f1 d/i`` marked, the EN 1990 limit drawn) and ``report.html`` — one self-contained page
(the figure embedded as base64 PNG, no other file needed): the verdict first, then the governing case, the inputs,
the assumptions with their clauses, the modes, the crossings that did not complete and the envelope's peak per
train."""
from __future__ import annotations

import base64
import html
from pathlib import Path

from .drawing import pyplot

__all__ = ["write_figures_and_report", "plot_envelope", "report_html", "PASS_COLOUR", "FAIL_COLOUR"]

#: the verdict banner's colour (RGB) for a pass and for a fail
PASS_COLOUR = (0x1B, 0x7F, 0x3A)
FAIL_COLOUR = (0xB3, 0x26, 0x1E)


def plot_envelope(envelope: list, summary: dict, resonances: dict, path: Path) -> None:
    """``envelope.png`` (module docstring); ``resonances``: (train, mass bound) -> resonance speeds [km/h]."""
    plt = pyplot()
    bounds = list(dict.fromkeys(r["mass_bound"] for r in envelope))
    fig, axes = plt.subplots(len(bounds), 1, figsize=(9, 3.6 * len(bounds)), squeeze=False)
    limit = summary["acceleration_limit_m_s2"]
    for ax, bound in zip(axes[:, 0], bounds):
        trains = list(dict.fromkeys(r["train"] for r in envelope if r["mass_bound"] == bound))
        for k, train in enumerate(trains):
            rows = sorted((r for r in envelope if r["mass_bound"] == bound and r["train"] == train),
                          key=lambda r: r["speed_kmh"])
            v = [r["speed_kmh"] for r in rows if r.get("max_deck_acceleration_m_s2") is not None]
            a = [r["max_deck_acceleration_m_s2"] for r in rows if r.get("max_deck_acceleration_m_s2") is not None]
            line, = ax.plot(v, a, "-", lw=1.2, label=train if len(train) < 20 else Path(train).stem)
            bad = [r["speed_kmh"] for r in rows if r.get("status") != "ok"]
            if bad:
                ax.plot(bad, [0.0] * len(bad), "x", color=line.get_color(), ms=8)
            for vr in resonances.get((train, bound), []):
                if v and min(v) <= vr <= max(v):            # the resonances inside the speeds run
                    ax.axvline(vr, color=line.get_color(), lw=0.6, ls=":")
        ax.axhline(limit, color="k", lw=1.5, ls="--", label=f"EN 1990 limit {limit:g} m/s²")
        ax.set_xlabel("speed [km/h]")
        ax.set_ylabel("max deck acceleration [m/s²]")
        ax.set_title(f"mass bound: {bound}")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=4)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _table(rows, header) -> str:
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def report_html(summary: dict, envelope: list, figure_png: bytes) -> str:
    """The report page (module docstring)."""
    ok = summary["verdict"] == "pass"
    g = summary.get("governing") or {}
    inp = summary["inputs"]
    a = summary["max_deck_acceleration_m_s2"]
    per_train = {}
    for r in envelope:
        x = r.get("max_deck_acceleration_m_s2")
        if x is not None and (r["train"] not in per_train or x > per_train[r["train"]][0]):
            per_train[r["train"]] = (x, r["speed_kmh"], r["mass_bound"])
    modes = [(bound, "as the modes file" if m['mass_kg_per_m'] is None else f"{m['mass_kg_per_m']:g}",
              ", ".join(f"{f:.3f}" for f in m["f1_Hz"]), m["n_modes"], f"{m['cutoff_Hz']:.1f}",
              "yes" if m["modes_reach_cutoff"] else "no") for bound, m in summary["modes"].items()]
    clauses = summary["clauses"]
    assumptions = [
        ("trains", "moving axle loads of " + ", ".join(inp["trains"]), clauses["trains"]),
        ("speeds", summary["speed_rule"], clauses["speeds"]),
        ("mass", ", ".join(f"{k} {'as the modes file' if v is None else f'{v:g} kg/m'}"
                           for k, v in inp["mass_kg_per_m"].items())
         + ("; the modes file's modes scaled to each mass (every mass scaled, the stiffness kept: ω/√r)"
            if inp.get("modes_file") else ""), clauses["mass"]),
        ("damping", f"ζ = {100 * summary['damping_ratio_used']:.3g} % ({summary['damping_rule']})",
         clauses["damping"]),
        ("modes", ("the modes file's modes up to the first vertical one at or above max(30 Hz, 1.5 f1, f3)"
                   if inp.get("modes_file") else "vertical bending modes of the continuous deck up to the first at "
                   "or above max(30 Hz, 1.5 f1, f3)" if inp.get("continuous") else
                   "vertical bending modes of every span up to the first at or above max(30 Hz, 1.5 f1, f3)"),
         clauses["modes"]),
        ("limit", f"{summary['acceleration_limit_m_s2']:g} m/s² ({inp['track_form']})", clauses["limit"]),
    ]
    failed = summary["not_completed"]
    img = base64.b64encode(figure_png).decode("ascii")
    colour = "#%02x%02x%02x" % (PASS_COLOUR if ok else FAIL_COLOUR)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>EN 1991-2 dynamic check: {summary['verdict'].upper()}</title>
<style>body{{font-family:sans-serif;max-width:980px;margin:2em auto;color:#222}}
.verdict{{font-size:2em;font-weight:bold;color:#fff;background:{colour};padding:.4em .8em;border-radius:6px}}
table{{border-collapse:collapse;margin:.5em 0}}td,th{{border:1px solid #bbb;padding:.25em .6em;text-align:left}}
th{{background:#eee}}</style></head><body>
<h1>EN 1991-2 §6.4.6 dynamic check</h1>
<p id="verdict" class="verdict">Verdict: {summary['verdict'].upper()}</p>
<p>{html.escape(summary['verdict_reason'])}.</p>
<h2>Governing case</h2>
{_table([(g.get('train', '-'), g.get('mass_bound', '-'), g.get('speed_kmh', '-'),
          '-' if a is None else f'{a:.4g}', summary['acceleration_limit_m_s2'])],
        ('train', 'mass bound', 'speed [km/h]', 'max deck acceleration [m/s²]', 'limit [m/s²]'))}
<p>Largest dynamic enhancement of the mid-span displacement against the static one:
{'-' if summary['max_dynamic_enhancement'] is None else f"{summary['max_dynamic_enhancement']:.3f}"}.</p>
<h2>Envelope</h2>
<img alt="deck acceleration against speed" src="data:image/png;base64,{img}" style="max-width:100%">
<h2>Inputs</h2>
{_table([('bridge file', inp['bridge_file']), ('spans [m]', ', '.join(f'{x:g}' for x in inp['spans_m'])),
         ('deck', summary['deck']),
         *([('EI [N m²]', f"{inp['EI_Nm2']:.4g}")] if inp['EI_Nm2'] is not None else []),
         *([('modes computed with [kg/m]', f"{inp['modes_mass_kg_per_m']:g}")]
           if inp.get('modes_mass_kg_per_m') is not None else []),
         ('structure', inp['structure']), ('track form', inp['track_form']),
         ('maximum line speed [km/h]', f"{inp['max_line_speed_kmh']:g}")], ('input', 'value'))}
<h2>Assumptions and clauses</h2>
{_table(assumptions, ('item', 'assumption', 'clause'))}
<h2>Modes</h2>
{_table(modes, ('mass bound', 'mass [kg/m]', 'f1 [Hz]', 'modes', 'cut-off [Hz]', 'modes reach it'))}
<h2>Peak per train</h2>
{_table([(t, f'{x:.4g}', v, b) for t, (x, v, b) in per_train.items()],
        ('train', 'max deck acceleration [m/s²]', 'at speed [km/h]', 'mass bound'))}
<h2>Crossings that did not complete</h2>
{_table([(r['train'], r['mass_bound'], r['speed_kmh'], r['status']) for r in failed],
        ('train', 'mass bound', 'speed [km/h]', 'status')) if failed else '<p>none</p>'}
<p>{summary['crossings']} crossings; every one in envelope.csv.</p>
</body></html>
"""


def write_figures_and_report(envelope: list, summary: dict, resonances: dict, out: Path) -> dict:
    """``envelope.png`` and ``report.html`` in ``out`` (``resonances``: (train, mass bound) -> resonance speeds
    [km/h]); their paths."""
    fig = out / "envelope.png"
    plot_envelope(envelope, summary, resonances, fig)
    page = out / "report.html"
    page.write_text(report_html(summary, envelope, fig.read_bytes()), encoding="utf-8")
    return {"envelope_csv": str(out / "envelope.csv"), "envelope_png": str(fig), "report_html": str(page),
            "summary_json": str(out / "summary.json")}
