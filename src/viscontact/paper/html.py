"""``index.html``: one self-contained page with every table and figure (reads results only)."""

from __future__ import annotations

import html
from datetime import datetime, timezone

from .experiment import data_source
from .study import PUBLISHED_E, StudyResults
from .figures import FIGURES
from .._support.report import PAGE_CSS, Table
from ..physics.laws import Jian

__all__ = ["render_index"]

def _tables_by_stem(tables: list[Table]) -> dict[str, Table]:
    return {t.stem: t for t in tables}


def _published_check(res: StudyResults) -> str:
    rows = []
    i = int(abs(res.alpha_grid - 0.3).argmin())
    for m, pub in PUBLISHED_E.items():
        ours = res.table2[0.5][i] if m == Jian.name else res.table1[m][i]
        rows.append(f"<tr><td>{m}{' (beta = 0.5)' if m == Jian.name else ''}</td>"
                    f'<td class="n">{pub:.4f}</td><td class="n">{ours:.6f}</td>'
                    f"<td>{'yes' if round(float(ours), 4) == pub else 'NO'}</td></tr>")
    return ('<table id="published"><caption><b>Check against the published values.</b> e at '
            "alpha = 0.3, zero-force end, as published by Jian et al. (2019).</caption><thead><tr><th>law</th>"
            "<th>published</th><th>this report</th><th>agrees to 4 decimals</th></tr></thead>"
            "<tbody>" + "".join(rows) + "</tbody></table>")


def render_index(res: StudyResults, tables: list[Table], version: str) -> str:
    """The report page: tables, figures with captions, the comparison with the drop tests."""
    e = html.escape
    t = _tables_by_stem(tables)
    figs = "\n".join(
        f'<figure id="{e(name[:-4])}"><img src="{e(name)}" alt="{e(caption)}">'
        f"<figcaption>{e(caption)}</figcaption></figure>"
        for name, (_draw, caption) in FIGURES.items()
    )
    files = ", ".join(f'<a href="{s}.csv">{s}.csv</a> / <a href="{s}.md">{s}.md</a>' for s in t)
    stamp = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>viscontact report: damping terms of viscoelastic contact models</title>
<style>{PAGE_CSS}</style></head>
<body>
<h1>Damping terms of viscoelastic contact force models: a reproduction</h1>
<p>Reproduction of the tables and figures of B. Jian et al., Powder Technology 356 (2019)
735-749 (doi:10.1016/j.powtec.2019.08.110) with <code>viscontact {e(version)}</code>,
generated {e(stamp)} by <code>viscontact reproduce</code>. Every collision is solved to a
relative tolerance of 1e-12; the contact ends when the force returns to zero.
Data: {e(data_source().rstrip('.'))}.</p>
<p>Tables as files: {files}.</p>

<h2>Comparison with the drop tests</h2>
<p class="note">Each law is calibrated so that it reproduces the measured e of each lacrosse
ball at v_i = 171.6 cm/s (the Jian law with the study's beta), so the predicted e equals the
measured one by construction. The contact time t_c and the peak force F_max are predictions.</p>
{t["comparison"].to_html()}

<h2>Tables</h2>
{t["table1"].to_html()}
{_published_check(res)}
{t["table2"].to_html()}
{t["table4"].to_html()}

<h2>Figures</h2>
{figs}
</body></html>
"""
