"""Writes the case-file and gear-set-file references from :mod:`cases.reference` (the table the
validators read) before the build, so the pages cannot drift from the code."""

from pathlib import Path

from cases.reference import reference_markdown


def _write(app):
    out = Path(app.srcdir) / "reference"
    out.mkdir(exist_ok=True)
    for kind in ("case", "gearset"):
        page = out / f"{kind}-file.md"
        text = reference_markdown(kind)
        if not page.is_file() or page.read_text() != text:  # unchanged: no rebuild
            page.write_text(text)


def setup(app):
    app.connect("builder-inited", _write)
    return {"parallel_read_safe": True}
