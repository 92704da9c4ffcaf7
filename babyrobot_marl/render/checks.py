"""The renderer's argument checks and its size limit: frame pixels, cell sizes, frame rates.

The rules for integers and reals are the core's (``core.checks``); this module only says what the
renderer allows and in which words.
"""

from __future__ import annotations

import math

MAX_FRAME_PIXELS = 4096 * 4096  # an rgb_array frame (48 MB of RGB): a 256x256 maze at 16-pixel cells


def check_frame_pixels(width: int, height: int, what: str = "cell_size", hint: str = "use a smaller cell_size") -> None:
    """An image of ``width x height`` pixels is within ``MAX_FRAME_PIXELS`` (checked before allocating it)."""
    if width * height > MAX_FRAME_PIXELS:
        raise ValueError(
            f"{what}: the frame would be {width}x{height} = {width * height:,} pixels, more than the limit of "
            f"{MAX_FRAME_PIXELS:,} ({3 * MAX_FRAME_PIXELS // 10**6} MB of RGB); {hint}"
        )


def max_cell_size(width_cells: int, height_cells: int, extra_height_px: int = 0) -> int:
    """The largest cell size (pixels) whose frame of ``width_cells x height_cells`` (plus a panel) fits the limit."""
    size = math.isqrt(MAX_FRAME_PIXELS // max(1, width_cells * height_cells))
    while size > 0 and size * width_cells * (size * height_cells + extra_height_px) > MAX_FRAME_PIXELS:
        size -= 1
    return size
