"""A virtual X display (Xvfb) for Exudyn's OpenGL renderer on machines without a screen (CI, servers).

>>> with VirtualDisplay() as display:                                      # doctest: +SKIP
...     subprocess.run([sys.executable, "-m", "exudyn_wheelrail.interactive.screenshot", "--out", "shots"],
...                    env=display.env(), check=True)

:class:`VirtualDisplay` starts ``Xvfb :N`` on the first free display number N (no lock file ``/tmp/.X{N}-lock``
and no socket ``/tmp/.X11-unix/X{N}``), waits until its socket exists and stops exactly that process on exit.
:func:`xvfb_available` says whether the ``Xvfb`` executable is on the PATH (Debian/Ubuntu: ``apt-get install
xvfb``; Mesa's software OpenGL, ``libgl1-mesa-dri``, draws the frames).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import time
from pathlib import Path

__all__ = ["VirtualDisplay", "xvfb_available"]


def xvfb_available() -> bool:
    """Whether the ``Xvfb`` executable is on the PATH."""
    return shutil.which("Xvfb") is not None


def _display_free(n: int) -> bool:
    return not Path(f"/tmp/.X{n}-lock").exists() and not Path(f"/tmp/.X11-unix/X{n}").exists()


class VirtualDisplay:
    """Context manager running ``Xvfb`` on a free display number (``first``, ``first + 1``, ...).

    ``screen`` is the screen geometry ``WIDTHxHEIGHTxDEPTH``; ``timeout_s`` the wait for the server's socket.
    Inside the context, :attr:`display` is ``":N"`` and :meth:`env` a copy of ``os.environ`` with ``DISPLAY`` set.
    """

    def __init__(self, screen: str = "1280x1024x24", first: int = 90, timeout_s: float = 10.0):
        self.screen = screen
        self.first = int(first)
        self.timeout_s = float(timeout_s)
        self.process: subprocess.Popen | None = None
        self.display: str | None = None

    def start(self) -> "VirtualDisplay":
        exe = shutil.which("Xvfb")
        if exe is None:
            raise RuntimeError("Xvfb is not installed (apt-get install xvfb)")
        for n in range(self.first, self.first + 100):
            if not _display_free(n):
                continue
            proc = subprocess.Popen([exe, f":{n}", "-screen", "0", self.screen, "-nolisten", "tcp"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
            t_end = time.monotonic() + self.timeout_s
            while time.monotonic() < t_end:
                if proc.poll() is not None:          # exited: the number was taken meanwhile, try the next one
                    break
                if Path(f"/tmp/.X11-unix/X{n}").exists():
                    self.process, self.display = proc, f":{n}"
                    return self
                time.sleep(0.05)
            if proc.poll() is None:
                proc.kill()
                proc.wait()
                raise RuntimeError(f"Xvfb :{n} did not open its socket within {self.timeout_s} s")
        raise RuntimeError(f"no free X display number in {self.first}..{self.first + 99}")

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.process = None

    def env(self) -> dict:
        """``os.environ`` with ``DISPLAY`` set to this display."""
        if self.display is None:
            raise RuntimeError("the virtual display is not running")
        env = dict(os.environ)
        env["DISPLAY"] = self.display
        return env

    def __enter__(self) -> "VirtualDisplay":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()
