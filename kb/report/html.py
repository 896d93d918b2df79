"""The page around the figures: escaping, tables, sections, the plotly figure divs and the
page shell with plotly.js inlined once (or, for a campaign's trial pages, one shared copy).

The plotly.js a page inlines is the smallest that draws its figures: a partial bundle shipped
in ``kb/report/js/`` (``bundles.json``: npm package, version, trace types) when every trace
type of the page is in it, else the plotly package's full plotly.js; a page without figures
gets none. plotly.js is most of a page's load time (docs/benchmarks.md, "Report pages").

Every text that comes from a file goes through :func:`esc` before it lands in the page (names
can hold ``<`` and ``&``); the figures' JSON is written by plotly, which escapes ``<``, ``>``
and ``/`` inside the script.
"""

from __future__ import annotations

import html
import json
import math
import re
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any, Iterable, Sequence

import plotly.io
import plotly.offline

#: plotly's options for every figure: no plotly logo, a picture button that saves a PNG.
CONFIG = {"displaylogo": False, "responsive": True,
          "toImageButtonOptions": {"format": "png", "scale": 2}}

STYLE = """
body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; margin: 0 auto; max-width: 1200px;
       padding: 0 1.2em 3em; color: #1d2430; background: #fff; }
h1 { font-size: 1.6em; margin: 0.8em 0 0.2em; } h2 { font-size: 1.25em; margin: 1.6em 0 0.4em;
  border-bottom: 1px solid #d8dde6; padding-bottom: 0.2em; } h3 { font-size: 1.05em; margin: 1.2em 0 0.3em; }
table { border-collapse: collapse; margin: 0.4em 0 0.8em; } caption { text-align: left; color: #555; }
th, td { border: 1px solid #d8dde6; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #f2f4f8; font-weight: 600; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
table.nested td, table.nested th { border-color: #e8ebf0; padding: 0.1em 0.4em; }
.facts { color: #444; margin: 0 0 0.6em; } .note { color: #666; font-style: italic; }
.ok { color: #176b2c; font-weight: 600; } .bad { color: #b3261e; font-weight: 600; }
.lost td { background: #fff6f5; } .plot { width: 100%; } .grid { display: grid; gap: 0.6em;
  grid-template-columns: repeat(auto-fill, minmax(270px, 1fr)); }
nav a { margin-right: 1em; } code { font-size: 0.95em; }
.keys { margin: 0.2em 0; } .key { margin-right: 1.1em; white-space: nowrap; }
.key i { display: inline-block; width: 0.9em; height: 0.9em; margin-right: 0.3em; vertical-align: -0.1em;
  border: 1px solid #0003; }
"""


def esc(value: Any) -> str:
    """``value`` as HTML text (``<``, ``>``, ``&`` and quotes escaped)."""
    return html.escape("" if value is None else str(value), quote=True)


def number(value: Any) -> str:
    """A number as a person reads it (integers plain, others to 4 significant figures)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return esc(value)
    if isinstance(value, int) or (math.isfinite(value) and value == int(value) and abs(value) < 1e15):
        return f"{int(value):,}"
    return f"{value:.4g}"


def yes_no(value: Any, yes: str = "yes", no: str = "no") -> str:
    """A coloured yes / no (None: a dash)."""
    if value is None:
        return "&ndash;"
    return f'<span class="ok">{yes}</span>' if value else f'<span class="bad">{no}</span>'


#: How deep :func:`value_html` nests tables before it shows the rest as JSON text.
MAX_DEPTH = 6


def cell(value: Any, depth: int = 0) -> str:
    """A table cell for any JSON value (objects and lists of objects as nested tables)."""
    if isinstance(value, bool):
        return f"<td>{yes_no(value)}</td>"
    if isinstance(value, (int, float)):
        return f'<td class="num">{number(value)}</td>'
    return f"<td>{value_html(value, depth)}</td>"


def value_html(value: Any, depth: int = 0) -> str:
    """Any JSON value as HTML: scalars as text, objects as a nested key / value table (an object
    of flat objects, such as a summary's statistics per metric, as one table with a row per
    name and a column per key), lists of scalars joined with commas, lists of objects as a
    nested table with a column per key;
    below :data:`MAX_DEPTH` levels, JSON text (cut at 200 characters)."""
    if depth > MAX_DEPTH and isinstance(value, (dict, list)):
        text = json.dumps(value, default=str)
        return f"<code>{esc(text[:200] + ('...' if len(text) > 200 else ''))}</code>"
    if value is None:
        return "&ndash;"
    if isinstance(value, bool):
        return yes_no(value)
    if isinstance(value, (int, float)):
        return number(value)
    if isinstance(value, dict):
        if not value:
            return "&ndash;"
        if len(value) > 1 and all(isinstance(v, dict) and v and all(not isinstance(x, (dict, list)) for x in v.values())
                                  for v in value.values()):  # {name: {stat: number}}: a row per name
            keys = list(dict.fromkeys(k for v in value.values() for k in v))
            return table(["", *keys], ([name, *(v.get(k) for k in keys)] for name, v in value.items()),
                         css="nested", depth=depth + 1)
        rows = "".join(f"<tr><th>{esc(k)}</th>{cell(v, depth + 1)}</tr>" for k, v in value.items())
        return f'<table class="nested">{rows}</table>'
    if isinstance(value, list):
        if value and all(isinstance(v, dict) for v in value):
            keys = list(dict.fromkeys(k for v in value for k in v))
            return table(keys, ([v.get(k) for k in keys] for v in value), css="nested", depth=depth + 1)
        return ", ".join(value_html(v, depth + 1) for v in value) or "&ndash;"
    return esc(value)


def table(headers: Sequence[str], rows: Iterable[Sequence[Any]], *, css: str = "", caption: str = "",
          raw: Sequence[bool] | None = None, row_css: Sequence[str] | None = None, tid: str = "",
          depth: int = 0) -> str:
    """An HTML table; ``raw[i]`` True: column ``i`` is HTML already (links), else a JSON value."""
    head = "".join(f"<th>{esc(h)}</th>" for h in headers)
    body = []
    for n, row in enumerate(rows):
        cells = "".join(f"<td>{v}</td>" if raw and raw[i] else cell(v, depth) for i, v in enumerate(row))
        cls = f' class="{row_css[n]}"' if row_css and row_css[n] else ""
        body.append(f"<tr{cls}>{cells}</tr>")
    attrs = (f' class="{css}"' if css else "") + (f' id="{tid}"' if tid else "")
    cap = f"<caption>{esc(caption)}</caption>" if caption else ""
    return f"<table{attrs}>{cap}<thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def section(title: str, body: str, sid: str = "") -> str:
    """A titled section of the page."""
    attr = f' id="{sid}"' if sid else ""
    return f"<section{attr}><h2>{esc(title)}</h2>{body}</section>"


def note(text: str) -> str:
    """A note in place of something the report does not have (text: escaped here)."""
    return f'<p class="note">{esc(text)}</p>'


def figure(fig: dict[str, Any], div_id: str, *, toolbar: bool = True) -> str:
    """The div of a plotly figure (a plain dict of data and layout) and a script that queues it
    for drawing once plotly.js has loaded (:data:`DRAW`); ``toolbar`` False: no mode bar."""
    layout = dict(fig.get("layout", {}))
    config = CONFIG if toolbar else {**CONFIG, "displayModeBar": False}
    spec = plotly.io.to_json({"data": fig.get("data", []), "layout": layout, "config": config}, validate=False,
                             remove_uids=True)
    height = layout.get("height", 450)
    types = " ".join(sorted({str(t.get("type") or "scatter") for t in fig.get("data", [])}))
    return (f'<div id="{esc(div_id)}" class="plot" data-traces="{esc(types)}" style="height:{int(height)}px"></div>'
            f'<script>kitkbPlots.push(["{esc(div_id)}", {spec}]);</script>')


#: Runs the inlined plotly.js once the text and tables have painted (the page holds it as text,
#: ``<script type="text/plain">``: run where it stands, it would hold the first paint back until
#: it is evaluated), then draws the queued figures, the flat ones first (the tables and 2-D plots show
#: at once, the 3-D view, which needs WebGL, last: drawn first, its first frame would hold the
#: flat ones back; docs/benchmarks.md, "Report pages"), yielding to the browser between figures;
#: ``<body data-drawn="N" data-drawn-ms="T">`` when all N are drawn, T ms after navigation
#: started (an error goes to the console). The 3-D view is drawn at the screen's pixel ratio
#: rather than plotly's default of 2 (four times the pixels on a common screen, each drawn in
#: software where the browser has no GPU). Marks for the benchmark: ``kitkb-plotly-ready`` and
#: a measure ``kitkb-draw ID`` per figure.
DRAW = """(async () => {
  const inlined = document.getElementById('kitkb-plotly-js');
  if (inlined) {  // after the first paint (a hidden tab does not paint: at once; at most 1 s)
    await new Promise(r => {
      if (document.visibilityState === 'hidden') return r();
      requestAnimationFrame(() => setTimeout(r, 0));
      setTimeout(r, 1000);
    });
    const script = document.createElement('script');
    script.textContent = inlined.textContent;
    inlined.remove();
    document.head.appendChild(script);
  }
  performance.mark('kitkb-plotly-ready');
  const is3d = fig => fig.data.some(t => String(t.type).endsWith('3d')) ? 1 : 0;
  const plots = window.kitkbPlots.slice().sort((a, b) => is3d(a[1]) - is3d(b[1]));
  const screenRatio = Math.min(2, Math.max(1, window.devicePixelRatio || 1));
  for (const [id, fig] of plots) {
    await new Promise(r => setTimeout(r, 0));
    const start = performance.now();
    fig.config.plotGlPixelRatio ??= screenRatio;  // WebGL at the screen's pixels (plotly's default: 2)
    try { await Plotly.newPlot(id, fig.data, fig.layout, fig.config); }
    catch (e) { console.error('kitkb report: figure ' + id + ' not drawn: ' + e); }
    performance.measure('kitkb-draw ' + id, {start});
  }
  document.body.dataset.drawnMs = String(Math.round(performance.now()));
  document.body.dataset.drawn = String(plots.length);
})();"""


@lru_cache(maxsize=1)
def plotly_js() -> str:
    """plotly.js, as shipped with the plotly package (about 4.7 MB): every trace type."""
    return plotly.offline.get_plotlyjs()


@dataclass(frozen=True)
class Bundle:
    """A partial plotly.js bundle of ``kb/report/js/`` (an entry of ``bundles.json``)."""

    name: str
    file: str
    package: str
    version: str
    sha256: str
    traces: frozenset[str]

    def text(self) -> str:
        """The bundle's JavaScript."""
        return _js_file(self.file)


@lru_cache(maxsize=1)
def bundles() -> tuple[Bundle, ...]:
    """The partial bundles shipped with kb.report, in the order of bundles.json: smallest first."""
    entries = json.loads(_js_file("bundles.json"))["bundles"]
    return tuple(Bundle(**{**e, "traces": frozenset(e["traces"])}) for e in entries)


@lru_cache(maxsize=None)
def _js_file(name: str) -> str:
    return resources.files(__package__).joinpath("js", name).read_text(encoding="utf-8")


#: A figure's trace types as :func:`figure` writes them on its div (escaped: a name holds no ``"``,
#: so none can forge it).
_TRACES = re.compile(r'<div id="[^"]*" class="plot" data-traces="([^"]*)"')


def trace_types(body: str) -> set[str] | None:
    """The trace types of the figures in ``body`` (HTML made with :func:`figure`); None: no figure."""
    found = [m.group(1) for m in _TRACES.finditer(body)]
    return {t for types in found for t in types.split()} if found else None


def bundle_for(types: Iterable[str]) -> Bundle | None:
    """The smallest shipped bundle that has every trace type of ``types``; None: the full plotly.js."""
    need = set(types)
    return next((b for b in bundles() if need <= b.traces), None)


def page_plotly_js(body: str) -> str:
    """The plotly.js that draws the figures of ``body``: a partial bundle, the full plotly.js, or
    nothing (no figure)."""
    types = trace_types(body)
    if types is None:
        return ""
    chosen = bundle_for(types)
    return chosen.text() if chosen is not None else plotly_js()


def page(title: str, body: str, *, script_src: str | None = None, plotly_js_text: str | None = None) -> str:
    """A whole HTML page: plotly.js inlined once (``script_src`` None): ``plotly_js_text``, or
    else the smallest plotly.js that draws the page's figures (:func:`page_plotly_js`); or
    loaded from the relative path ``script_src`` (a campaign's trial pages share one copy). At
    the end of the body, so that the text and tables show before the figures are drawn."""
    if script_src is None:
        js = page_plotly_js(body) if plotly_js_text is None else plotly_js_text
        script = f'<script type="text/plain" id="kitkb-plotly-js">{js}</script>' if js else ""
    else:
        script = f'<script type="text/javascript" src="{esc(script_src)}"></script>'
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<meta name=\"generator\" content=\"kitkb report\">\n<title>{esc(title)}</title>\n"
            f"<style>{STYLE}</style>\n<script>window.kitkbPlots = [];</script>\n</head>\n<body>\n{body}\n"
            f"{script}\n<script>{DRAW}</script>\n</body>\n</html>\n")
