"""Rasterise the glyphs that ``rgb_array`` draws text with (run offline; needs Pillow).

``python -m babyrobot_marl.render.fontgen [FONT.ttf]`` writes ``data/glyphs.npz``: Liberation
Sans Bold (SIL Open Font License 1.1, ``data/OFL.txt``), printable ASCII, at the pixel sizes in
``SIZES``, each glyph an 8-bit coverage mask cropped to its ink with its offset and advance.
The live canvas draws text with the same font (``'Liberation Sans', Arial``: the same metrics),
so both renderers lay text out alike. The package itself never imports Pillow.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

SIZES = (*range(6, 21), *range(22, 42, 2), 44, 48, 52, 58, 64)
CHARS = "".join(chr(c) for c in range(32, 127))
DEFAULT_FONT = "/usr/share/fonts/truetype/liberation2/LiberationSans-Bold.ttf"
OUT = Path(__file__).with_name("data") / "glyphs.npz"


def main(font_path: str = DEFAULT_FONT) -> None:
    from PIL import ImageFont

    bitmaps, table, metrics = [], [], []
    offset = 0
    for s in SIZES:
        font = ImageFont.truetype(font_path, s)
        ascent, descent = font.getmetrics()
        metrics.append((s, ascent, descent))
        for ch in CHARS:
            advance = font.getlength(ch)
            x0, y0, x1, y1 = font.getbbox(ch)  # anchor "la": left, ascender
            if x1 <= x0 or y1 <= y0:
                table.append((s, ord(ch), 0, 0, 0, 0, offset, round(advance * 64)))
                continue
            mask = font.getmask(ch)
            w, h = mask.size
            glyph = np.frombuffer(bytes(mask), dtype=np.uint8).reshape(h, w)
            bitmaps.append(glyph.ravel())
            table.append((s, ord(ch), x0, y0, w, h, offset, round(advance * 64)))
            offset += w * h
    np.savez_compressed(
        OUT,
        bitmaps=np.concatenate(bitmaps),
        table=np.array(table, dtype=np.int32),  # size, char, x0, y0, w, h, offset, advance * 64
        metrics=np.array(metrics, dtype=np.int32),  # size, ascent, descent
    )
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes)")


if __name__ == "__main__":
    main(*sys.argv[1:])
