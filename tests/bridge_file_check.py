"""A bridge file given to ``en1991-dynamic`` and what the command says about it (the bad-input tests of the EN 1991-2
check share it)."""
from __future__ import annotations

from exudyn_wheelrail.cli import main


def check_bridge_file(tmp_path, capsys, body: str):
    """Write ``[bridge]`` + ``body`` to ``tmp_path/b.toml``, run the command on it; ``(exit code, stderr stripped,
    the file, the output folder)``."""
    f = tmp_path / "b.toml"
    f.write_text("[bridge]\n" + body)
    out = tmp_path / "o"
    code = main(["en1991-dynamic", "--bridge", str(f), "--max-line-speed-kmh", "200", "--out", str(out)])
    return code, capsys.readouterr().err.strip(), f, out
