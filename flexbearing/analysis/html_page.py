"""A report's Markdown as one self-contained HTML page (tables, headings, lists, embedded plots).

`flexbearing report` and `flexbearing study` write their results as Markdown (report.md,
study.md) beside PNG plots. The same text is also written as report.html / study.html, one file
that opens in any browser and can be mailed or attached as it is: every `![alt](plot.png)` of
the Markdown becomes an <img> whose source is the PNG itself, base64-encoded in a data URI
(RFC 2397), so nothing else has to travel with it.

Only the Markdown the reports write is understood (not general Markdown):

    # / ## / ### heading          -> <h1> / <h2> / <h3>
    | a | b |  + |---|---:| row   -> <table> with a header row; ---: columns right-aligned
    - item                        -> <ul><li>
    ![alt](file.png)              -> <figure><img src="data:image/png;base64,..."></figure>
    blank-line separated text     -> <p>
    `code`, **bold** inside text  -> <code>, <strong>
    &nbsp; and other character references are kept as they are

Text is HTML-escaped before the inline markup is applied, so a label such as "e/Cg < 1" or
"Fa & Fr" survives. An image whose file is missing is kept as its alt text with a note, not an
error: the report's tables are what matters and they never depend on a plot. The alt text is the
figure's caption. The print style (@media print) lays the page out on A4, keeps headings with
what follows and never splits a figure or a table row across pages (flexbearing.analysis.pdf
prints it through headless Chromium).
"""
from __future__ import annotations

import base64
import html
import re
from pathlib import Path

_IMAGE = re.compile(r"^!\[([^\]]*)\]\(([^)]+)\)$")
_CODE = re.compile(r"`([^`]+)`")
_BOLD = re.compile(r"\*\*([^*]+)\*\*")
_ALIGN_ROW = re.compile(r"^\|(\s*:?-+:?\s*\|)+$")

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 80em; padding: 0 1em; color: #222; }
table { border-collapse: collapse; margin: 0.8em 0 1.4em; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.6em; }
th { background: #eef1f5; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; }
tr:nth-child(even) td { background: #fafafa; }
code { background: #f2f2f2; padding: 0 0.2em; }
figure { margin: 1em 0; } figure img { max-width: 100%; }
figcaption { font-size: 0.85em; color: #555; }
@page { size: A4; margin: 14mm 12mm; }
@media print {
  body { max-width: none; margin: 0; padding: 0; font-size: 9pt; }
  table { font-size: 7.5pt; }
  thead { display: table-header-group; }
  h1, h2, h3 { break-after: avoid; }
  tr, figure, img { break-inside: avoid; }
  figure img { max-height: 125mm; width: auto; }
  tr:nth-child(even) td { background: none; }
  th { background: #eee; -webkit-print-color-adjust: exact; print-color-adjust: exact; }
}
"""


_ENTITY = re.compile(r"&amp;(#?[A-Za-z0-9]+);")


def inline(text: str) -> str:
    """Escaped text with `code` and **bold** turned into <code> and <strong>; character
    references the Markdown writes on purpose (&nbsp;) are kept."""
    out = _ENTITY.sub(r"&\1;", html.escape(text, quote=False))
    out = _CODE.sub(lambda m: f"<code>{m.group(1)}</code>", out)
    return _BOLD.sub(lambda m: f"<strong>{m.group(1)}</strong>", out)


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def _table(lines: list[str]) -> str:
    head = _cells(lines[0])
    has_align = len(lines) > 1 and _ALIGN_ROW.match(lines[1].replace(" ", ""))
    align = _cells(lines[1]) if has_align else ["---"] * len(head)
    right = [a.endswith(":") for a in align]
    body = lines[2:] if has_align else lines[1:]

    def row(cells, tag):
        num = ' class="num"'
        return "<tr>" + "".join(
            f"<{tag}{num if j < len(right) and right[j] else ''}>{inline(c)}</{tag}>"
            for j, c in enumerate(cells)) + "</tr>"
    return ("<table>\n<thead>" + row(head, "th") + "</thead>\n<tbody>\n"
            + "\n".join(row(_cells(b), "td") for b in body) + "\n</tbody>\n</table>")


def _figure(alt: str, src: str, folder: Path) -> str:
    path = folder / src
    if not path.is_file():
        return f"<p>[{inline(alt)}: plot {inline(src)} not found]</p>"
    mime = "image/svg+xml" if path.suffix.lower() == ".svg" else "image/png"
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (f'<figure><img alt="{html.escape(alt)}" src="data:{mime};base64,{data}">'
            f"<figcaption>{inline(alt)}</figcaption></figure>")


def markdown_to_html(text: str, folder, title: str = "flexbearing report") -> str:
    """The report Markdown `text` (module doc) as a complete HTML page; images are read from `folder`."""
    folder = Path(folder)
    blocks: list[str] = []
    para: list[str] = []
    items: list[str] = []
    table: list[str] = []

    def flush():
        if para:
            blocks.append("<p>" + inline(" ".join(para)) + "</p>")
            para.clear()
        if items:
            blocks.append("<ul>\n" + "\n".join(f"<li>{inline(i)}</li>" for i in items) + "\n</ul>")
            items.clear()
        if table:
            blocks.append(_table(table))
            table.clear()

    for raw in text.splitlines():
        line = raw.rstrip()
        if line.startswith("|"):
            if not table:
                flush()
            table.append(line)
            continue
        if table:
            flush()
        if not line.strip():
            flush()
        elif m := re.match(r"^(#{1,3}) (.*)$", line):
            flush()
            n = len(m.group(1))
            blocks.append(f"<h{n}>{inline(m.group(2))}</h{n}>")
        elif m := _IMAGE.match(line.strip()):
            flush()
            blocks.append(_figure(m.group(1), m.group(2), folder))
        elif line.startswith("- "):
            if para:
                flush()
            items.append(line[2:])
        elif items and line.startswith("  "):
            items[-1] += " " + line.strip()       # a wrapped list item
        else:
            if items:
                flush()
            para.append(line.strip())
    flush()
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{html.escape(title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
            + "\n".join(blocks) + "\n</body>\n</html>\n")


def write_html(markdown_path, title: str | None = None) -> Path:
    """Write <name>.html beside a report's <name>.md (images embedded); returns its path."""
    md = Path(markdown_path)
    out = md.with_suffix(".html")
    text = md.read_text()
    first = next((l[2:] for l in text.splitlines() if l.startswith("# ")), md.stem)
    out.write_text(markdown_to_html(text, md.parent, title or first))
    return out
