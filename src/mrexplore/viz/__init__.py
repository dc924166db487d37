"""Pictures of a run: animation frames, GIFs, MP4s, HTML replays and summary figures.

Everything here reads a run record (the arrays of ``trace.npz``: ``truth``,
``first_known``, ``positions`` and optionally ``alive``, ``goals``, ``component``,
``link_bits``, ``robot_first_known`` and, from noisy runs, ``estimated_positions``,
``localisation_error``, ``robot_belief``, see :mod:`mrexplore.trace`) and writes
images, so any saved run can be viewed later:

* :mod:`mrexplore.viz.render`: single frames, a plain GIF, the summary PNG;
* :mod:`mrexplore.viz.animate`: the run's animation (GIF or MP4) with links,
  targets, a header and optional per-robot belief panels;
* :mod:`mrexplore.viz.replay`: the self-contained ``replay.html``;
* :mod:`mrexplore.viz.noise`: a noisy run's arrays read once for the animation,
  the final picture and the replay (believed positions, each robot's own belief);
* :mod:`mrexplore.viz.plots`: figures of sweeps (curves with bands, metric vs a
  scenario value, bytes by type, group diameter), one colour per strategy.

Frames, GIFs and replays are pure numpy + Pillow; the figures use matplotlib,
which is imported inside the functions that draw them, so ``import mrexplore.viz``
stays light and works without the ``viz`` extra installed.
"""

from __future__ import annotations

from mrexplore.viz.animate import RunAnimator, ffmpeg_path, save_animation
from mrexplore.viz.render import (
    BELIEF_WRONG_FREE_RGB,
    BELIEF_WRONG_OCCUPIED_RGB,
    KNOWN_FREE_RGB,
    KNOWN_OCCUPIED_RGB,
    ROBOT_COLOURS,
    UNKNOWN_FREE_RGB,
    UNKNOWN_OCCUPIED_RGB,
    coverage_plot_png,
    frame_ticks,
    render_frame,
    robot_colour,
    save_final_png,
    save_gif,
)
from mrexplore.viz.replay import replay_html, write_replay

__all__ = [
    "BELIEF_WRONG_FREE_RGB",
    "BELIEF_WRONG_OCCUPIED_RGB",
    "KNOWN_FREE_RGB",
    "KNOWN_OCCUPIED_RGB",
    "ROBOT_COLOURS",
    "UNKNOWN_FREE_RGB",
    "UNKNOWN_OCCUPIED_RGB",
    "RunAnimator",
    "coverage_plot_png",
    "ffmpeg_path",
    "frame_ticks",
    "render_frame",
    "replay_html",
    "robot_colour",
    "save_animation",
    "save_final_png",
    "save_gif",
    "write_replay",
]
