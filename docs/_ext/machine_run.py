"""Sphinx extension: the whole-machine guide's console transcripts, generated.

On ``builder-inited`` it runs ``cyclomech run`` and ``cyclomech sweep`` on the STB
loom example (in this process, figures off, into a temporary folder) and writes
what they print to ``guide/_generated/loom_run.txt`` and ``loom_sweep.txt`` under
the documentation's source directory, so the guide shows what the commands print
today. A command that fails (an exit status other than 0) fails the build.
"""

from __future__ import annotations

import contextlib
import io
import re
import tempfile
from pathlib import Path
from typing import Any

#: Where the transcripts go, relative to the documentation's source directory.
TARGET = Path("guide") / "_generated"
#: The commands, as a user types them from the repository's root, by file name.
COMMANDS = {
    "loom_run.txt": ["run", "examples/stb_loom.toml", "--out", "out/stb_loom"],
    "loom_sweep.txt": [
        "sweep",
        "examples/stb_loom.toml",
        "--set",
        "lifter.preload_m=1e-4:4e-4:4",
        "--speed",
        "200:500:31",
        "--out",
        "out/stb_loom_sweep",
    ],
}


def transcript(argv: list[str], root: Path) -> str:
    """What ``cyclomech ARGV`` prints, run from ``root`` with its output folder in
    a temporary directory (shown as the command's own ``--out``), the timings
    replaced by ``…`` so that the page does not change on every build.

    >>> root = Path(__file__).resolve().parents[2]
    >>> text = transcript(["run", "examples/stb_loom.toml", "--out", "out/x"], root)
    >>> text.splitlines()[0]
    '$ cyclomech run examples/stb_loom.toml --out out/x'
    """
    from cyclomech.cli import main

    out = argv[argv.index("--out") + 1]
    buf = io.StringIO()
    with tempfile.TemporaryDirectory() as tmp, contextlib.chdir(root):
        args = [*argv[: argv.index("--out") + 1], tmp, "--quiet"]
        if argv[0] == "run":
            args.append("--no-plot")
        with contextlib.redirect_stdout(buf):
            status = main(args)
        if status != 0:
            raise RuntimeError(f"cyclomech {' '.join(args)} exited with status {status}")
        text = buf.getvalue().replace(tmp, out)
    text = re.sub(r"\bin \d+\.\d+ s\b", "in … s", text)
    text = re.sub(r"\(\d+ files in ", "(files in ", text)
    return f"$ cyclomech {' '.join(argv)}\n{text}"


def write(srcdir: str | Path) -> list[Path]:
    """Write the transcripts under ``srcdir``; an unchanged one is not rewritten."""
    root = Path(__file__).resolve().parents[2]
    paths = []
    for name, argv in COMMANDS.items():
        path = Path(srcdir) / TARGET / name
        text = transcript(argv, root)
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text, encoding="utf-8")
        paths.append(path)
    return paths


def _on_builder_inited(app: Any) -> None:
    write(app.srcdir)


def setup(app: Any) -> dict[str, Any]:
    """Register the extension with Sphinx."""
    app.connect("builder-inited", _on_builder_inited)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
