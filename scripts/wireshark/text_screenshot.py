#!/usr/bin/env python3
"""Renders text (tshark's output) as a PNG in a terminal's colours, for docs/wireshark.md.

    text_screenshot.py TEXT_FILE OUT.png

Needs Pillow (Debian: python3-pil) and the DejaVu Sans Mono font (fonts-dejavu-core); a tool for
the docs only, not part of any profile. Lines starting with "#" are drawn as headings.
"""
import sys

from PIL import Image, ImageDraw, ImageFont

FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
SIZE, PAD = 14, 12


def main():
    lines = open(sys.argv[1], encoding="utf-8").read().rstrip("\n").split("\n")
    font = ImageFont.truetype(FONT, SIZE)
    bold = ImageFont.truetype(FONT.replace("Mono.ttf", "Mono-Bold.ttf"), SIZE)
    width = max(font.getlength(line) for line in lines) + 2 * PAD
    step = SIZE + 4
    image = Image.new("RGB", (int(width), len(lines) * step + 2 * PAD), (30, 30, 30))
    draw = ImageDraw.Draw(image)
    for row, line in enumerate(lines):
        heading = line.startswith("#")
        draw.text((PAD, PAD + row * step), line.lstrip("# ") if heading else line,
                  fill=(255, 200, 90) if heading else (225, 225, 225), font=bold if heading else font)
    image.save(sys.argv[2])


if __name__ == "__main__":
    main()
