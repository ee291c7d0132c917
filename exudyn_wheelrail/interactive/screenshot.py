"""Screenshots of the RTRI model in Exudyn's renderer (needs an X display; :mod:`.headless` gives a virtual one).

    python -m exudyn_wheelrail.interactive.screenshot --out DIR [--steps 20] [--size 800x600] [--focus vehicle]

Builds the RTRI case (its spec, :func:`~exudyn_wheelrail.scenarios.scenario.build_scenario`; defaults: 20 m span,
250 km/h; Newmark 1 ms) with the 3-D view (:class:`~.view3d.WheelRailView`), runs ``steps`` steps (the one solve
wrapper), draws the final state and saves two PNG frames with ``SC.renderer.RedrawAndSaveImage()``
(``visualizationSettings.exportImages``):
``with_contacts.png`` (contact points and force arrows in :data:`~.view3d.CONTACT_RGBA`) and
``without_contacts.png`` (the same frame with ``show_contact_forces = False``).  Prints one JSON line with the
paths, the image size, the number of contacts drawn and the time of the frame.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

__all__ = ["rtri_screenshots", "main"]


def rtri_screenshots(out_dir, steps: int = 20, size=(800, 600), focus: str = "leading_bogie", case=None) -> dict:
    """Render the two frames (module docstring) into ``out_dir``; returns ``{"with_contacts": path,
    "without_contacts": path, "size": [w, h], "contacts_drawn": n, "time_s": t}``."""
    from ..multibody import connector as C
    from ..scenarios.rtri import RtriCase
    from ..scenarios.scenario import build_scenario, run_model
    from .view3d import WheelRailView, check_display

    check_display()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    case = case or RtriCase(duration_s=int(steps) * RtriCase().run.dt_s)
    h = build_scenario(case.scenario())
    view = WheelRailView.for_rtri(h)
    outcome = run_model(h, progress=False)
    if not outcome.status.ok:
        raise RuntimeError(f"the RTRI run ended {outcome.status}")
    res = view.show_current_state()
    n_contacts = int(((res[:, :, C.RES_STATUS] > 0) & (res[:, :, C.RES_N] > 0.0)).sum())
    SC = h.system_container
    view.configure(SC, focus=focus, window_size=size, show_text=False)
    ex = SC.visualizationSettings.exportImages
    ex.saveImageSingleFile = True
    ex.saveImageFormat = "PNG"
    ex.widthAlignment = 1
    ex.heightAlignment = 1
    if not SC.renderer.Start():
        raise RuntimeError("Exudyn's renderer could not be started (no X display? run under Xvfb)")
    paths = {}
    try:
        view.apply_camera(SC)
        for name, show in (("with_contacts", True), ("without_contacts", False)):
            view.show_contact_forces = show
            ex.saveImageFileName = str(out / name)
            SC.renderer.RedrawAndSaveImage()
            paths[name] = str(out / f"{name}.png")
    finally:
        SC.renderer.Stop()
    return {**paths, "size": [int(size[0]), int(size[1])], "contacts_drawn": n_contacts,
            "time_s": float(h.mbs.systemData.GetTime())}


def _size(text: str):
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--size expects WIDTHxHEIGHT, got {text!r}") from None
    if not (64 <= w <= 4096 and 64 <= h <= 4096):
        raise argparse.ArgumentTypeError(f"--size {text}: each side must be 64 ... 4096 pixels")
    return w, h


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--steps", type=int, default=20, help="time steps of 1 ms before the frame (default 20)")
    ap.add_argument("--size", type=_size, default=(800, 600), help="image size WIDTHxHEIGHT (default 800x600)")
    ap.add_argument("--focus", default="leading_bogie", choices=("leading_bogie", "vehicle"))
    args = ap.parse_args(argv)
    if args.steps < 1:
        ap.error("--steps must be positive")
    print(json.dumps(rtri_screenshots(args.out, steps=args.steps, size=args.size, focus=args.focus)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
