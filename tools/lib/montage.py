#!/usr/bin/env python3
"""Frames side by side in one PNG (the README's strip of an animation's frames):
    montage.py OUT.png COLUMNS FRAME.png ...
Needs Pillow (Debian's python3-pil, which python3-matplotlib brings)."""
import sys

from PIL import Image


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    out, columns, files = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
    frames = [Image.open(f).convert("RGB") for f in files]
    w, h = frames[0].size
    rows = (len(frames) + columns - 1) // columns
    sheet = Image.new("RGB", (w * columns, h * rows))
    for i, frame in enumerate(frames):
        sheet.paste(frame, ((i % columns) * w, (i // columns) * h))
    sheet.save(out, optimize=True)


if __name__ == "__main__":
    main()
