"""Pictures of a run: animation frames, GIFs and summary figures.

Everything here reads a run record (``truth``, ``first_known``, ``positions`` and
optionally ``alive``, see :mod:`mrexplore.viz.render`) and writes images. Frames and
GIFs are pure numpy + Pillow; the figures use matplotlib, which is imported inside
the functions that draw them, so ``import mrexplore.viz`` stays light and works
without the ``viz`` extra installed.
"""

from __future__ import annotations

from mrexplore.viz.render import (
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

__all__ = [
    "KNOWN_FREE_RGB",
    "KNOWN_OCCUPIED_RGB",
    "ROBOT_COLOURS",
    "UNKNOWN_FREE_RGB",
    "UNKNOWN_OCCUPIED_RGB",
    "coverage_plot_png",
    "frame_ticks",
    "render_frame",
    "robot_colour",
    "save_final_png",
    "save_gif",
]
