"""What every gallery script starts from, after sphinx-gallery's own reset of matplotlib."""

from __future__ import annotations

import matplotlib


def pillow_writer(gallery_conf, fname) -> None:
    """Save animations (the thumbnail of an animated example) with Pillow, which needs no
    ffmpeg binary, instead of matplotlib's default ffmpeg and its "unavailable" warning."""
    matplotlib.rcParams["animation.writer"] = "pillow"
