"""Turn the repository's Markdown references (FORMATS.md, RUBBER_TOML.md) into reST pages.

The file-format pages of the site are generated from the Markdown files that ship beside the
code, so that the site and the repository never disagree. Only the Markdown those files use is
understood: ``#`` headings, fenced code blocks, pipe tables, ``-`` lists and paragraphs with
inline code, bold text and links.
"""
import re
from pathlib import Path

#: (Markdown source relative to the repository root, generated page relative to docs/, title)
PAGES = [
    ("FORMATS.md", "formats/height_files.rst"),
    ("friction/RUBBER_TOML.md", "formats/rubber_toml.rst"),
    ("pipelines/diagnosis/CAPTIF_EXAMPLE.md", "reference/captif_diagnosis.rst"),
]
#: every docs/md/NAME.md becomes reference/NAME.rst
MD_FOLDER, MD_TARGET = "docs/md", "reference"
_UNDERLINE = {1: "=", 2: "-", 3: "~", 4: "^"}


def _inline(text):
    """Markdown inline text -> reST: `code`, **bold**, [text](url); everything else escaped."""
    out = []
    # a link whose text is code: the code alone (a relative link has no target on the site)
    text = re.sub(r"\[(`[^`]+`)\]\(([^)]+)\)",
                  lambda m: m.group(1) if not m.group(2).startswith("http") else m.group(1) + f" ({m.group(2)})",
                  text)
    for i, part in enumerate(re.split(r"(`[^`]+`)", text)):
        if i % 2:
            code = part[1:-1].strip()
            out.append(f"``{code}``" if code else "")
            continue
        links = []

        def keep_link(m):
            links.append((m.group(1), m.group(2)))
            return f"\x00{len(links) - 1}\x00"

        part = re.sub(r"\[([^\]]+)\]\(([^)]+)\)", keep_link, part)
        bolds = []

        def keep_bold(m):
            bolds.append(m.group(1))
            return f"\x01{len(bolds) - 1}\x01"

        part = re.sub(r"\*\*([^*]+?)\*\*", keep_bold, part)
        part = part.replace("\\", "\\\\")
        for ch in "*|_`[":
            part = part.replace(ch, "\\" + ch)
        part = re.sub(r"\x01(\d+)\x01", lambda m: f"**{_escape(bolds[int(m.group(1))])}**", part)
        part = re.sub(r"\x00(\d+)\x00", lambda m: _link(*links[int(m.group(1))]), part)
        out.append(part)
    # reST inline markup must be separated from surrounding word characters by an escaped space
    for k in range(1, len(out), 2):
        if out[k] and out[k - 1] and not out[k - 1][-1].isspace() and out[k - 1][-1] not in "(/'\"[":
            out[k - 1] += "\\ "
        if out[k] and k + 1 < len(out) and out[k + 1] and out[k + 1][0] not in " .,;:)!?'\"/-]":
            out[k + 1] = "\\ " + out[k + 1]
    return "".join(out)


def _escape(text):
    for ch in "*|_`":
        text = text.replace(ch, "\\" + ch)
    return text


def _link(text, url):
    if url.startswith("http"):
        return f"`{_escape(text)} <{url}>`__"
    return _escape(text)          # a repository-relative link: the text only


def _table(rows):
    cells = [[c.strip().replace("\x02", "|") for c in
              r.replace("\\|", "\x02").strip().strip("|").split("|")] for r in rows]
    header, body = cells[0], [r for r in cells[2:]]
    n = len(header)
    width = [max(len(r[j]) if j < len(r) else 0 for r in [header] + body) for j in range(n)]
    width = [max(4, round(10 * w ** 0.5)) for w in width]   # long cells wrap, short ones stay narrow
    lines = [".. list-table::", "   :header-rows: 1", "   :widths: " + " ".join(map(str, width)), ""]
    for row in [header] + body:
        row = (row + [""] * n)[:n]
        for j, c in enumerate(row):
            lines.append(("   * - " if j == 0 else "     - ") + (_inline(c) or ".."))
    return lines + [""]


def md_to_rst(md):
    """Convert one Markdown document (the subset described in the module docstring) to reST."""
    out, lines, i = [], md.splitlines(), 0
    while i < len(lines):
        line = lines[i]
        m = re.match(r"^(#{1,4}) (.*)$", line)
        if m:
            title = _inline(m.group(2).strip())
            out += [title, _UNDERLINE[len(m.group(1))] * max(len(title), 4), ""]
            i += 1
        elif line.startswith("<!--"):
            while i < len(lines) and "-->" not in lines[i]:
                i += 1
            i += 1
        elif line.startswith("```"):
            lang = line[3:].strip() or "text"
            j = i + 1
            block = []
            while j < len(lines) and not lines[j].startswith("```"):
                block.append(lines[j])
                j += 1
            out += [f".. code-block:: {lang}", ""] + ["   " + b if b else "" for b in block] + [""]
            i = j + 1
        elif line.startswith("|"):
            j = i
            while j < len(lines) and lines[j].startswith("|"):
                j += 1
            out += _table(lines[i:j])
            i = j
        elif re.match(r"^\s*[-*] ", line):
            item_indent = len(line) - len(line.lstrip())
            text = line.strip()[2:]
            j = i + 1
            while j < len(lines) and lines[j].strip() and not re.match(r"^\s*[-*] ", lines[j]) \
                    and not lines[j].startswith(("#", "|", "```")):
                text += " " + lines[j].strip()
                j += 1
            pad = "  " if item_indent >= 2 else ""
            out += [pad + "- " + _inline(text)]
            i = j
            if i < len(lines) and not re.match(r"^\s*[-*] ", lines[i]):
                out.append("")
        elif not line.strip():
            out.append("")
            i += 1
        else:
            j = i
            para = []
            while j < len(lines) and lines[j].strip() and not lines[j].startswith(("#", "|", "```")) \
                    and not re.match(r"^\s*[-*] ", lines[j]):
                para.append(lines[j].strip())
                j += 1
            out += [_inline(" ".join(para)), ""]
            i = j
    return "\n".join(_fix_nested_lists(out)) + "\n"


def _fix_nested_lists(lines):
    """A nested list in reST needs a blank line before and after it."""
    fixed = []
    for k, line in enumerate(lines):
        prev = fixed[-1] if fixed else ""
        nested, prev_nested = line.startswith("  - "), prev.startswith("  - ")
        if (nested != prev_nested) and prev.strip() and line.strip():
            fixed.append("")
        fixed.append(line)
    return fixed


def generate(app):
    """Write the generated pages (called when Sphinx starts reading)."""
    docs = Path(app.srcdir)
    root = docs.parent
    pages = list(PAGES) + [(f"{MD_FOLDER}/{p.name}", f"{MD_TARGET}/{p.stem}.rst")
                           for p in sorted((root / MD_FOLDER).glob("*.md"))]
    for src, dest in pages:
        target = docs / dest
        target.parent.mkdir(parents=True, exist_ok=True)
        text = md_to_rst((root / src).read_text(encoding="utf-8"))
        note = f".. This page is generated from {src} at build time; edit that file.\n\n"
        if not target.exists() or target.read_text(encoding="utf-8") != note + text:
            target.write_text(note + text, encoding="utf-8")


def setup(app):
    app.connect("builder-inited", generate)
    return {"parallel_read_safe": True, "version": "1"}
