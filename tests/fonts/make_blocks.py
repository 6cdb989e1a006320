"""Writes blocks.ttf, the tests' font: block letters of known outlines, advances and kerning.

Made here, not taken from anywhere (no licence to track). Run with fontTools installed
(`pip install fonttools`): `python3 make_blocks.py` beside this file. 1000 units per em:
  I  the rectangle [100, 300] x [0, 700], advance 400
  O  the square [100, 700] x [0, 700] less the hole [250, 550] x [150, 550], advance 800
  D  a stem and a bowl of two quadratic arcs through (700, 350), advance 800
  space  no outline, advance 300
and the kerning pair I O of -50 units in a `kern` table (format 0), as POV-Ray reads it.
"""

from fontTools.fontBuilder import FontBuilder
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib import newTable
from fontTools.ttLib.tables._k_e_r_n import KernTable_format_0


def rectangle(pen, x0, y0, x1, y1, clockwise=True):
    corners = [(x0, y0), (x0, y1), (x1, y1), (x1, y0)]
    if not clockwise:
        corners.reverse()
    pen.moveTo(corners[0])
    for corner in corners[1:]:
        pen.lineTo(corner)
    pen.closePath()


def glyph(draw):
    pen = TTGlyphPen(None)
    draw(pen)
    return pen.glyph()


def draw_d(pen):
    pen.moveTo((100, 0))
    pen.lineTo((100, 700))
    pen.lineTo((400, 700))
    pen.qCurveTo((700, 700), (700, 350))
    pen.qCurveTo((700, 0), (400, 0))
    pen.closePath()


glyphs = {
    ".notdef": glyph(lambda pen: rectangle(pen, 50, 0, 450, 700)),
    "space": glyph(lambda pen: None),
    "I": glyph(lambda pen: rectangle(pen, 100, 0, 300, 700)),
    "O": glyph(lambda pen: (rectangle(pen, 100, 0, 700, 700),
                            rectangle(pen, 250, 150, 550, 550, clockwise=False))),
    "D": glyph(draw_d),
}
order = list(glyphs)
# Advance and left side bearing (the outline's least x) of each glyph.
metrics = {".notdef": (500, 50), "space": (300, 0), "I": (400, 100), "O": (800, 100), "D": (800, 100)}

builder = FontBuilder(1000, isTTF=True)
builder.setupGlyphOrder(order)
builder.setupCharacterMap({ord(" "): "space", ord("I"): "I", ord("O"): "O", ord("D"): "D"})
builder.setupGlyf(glyphs)
builder.setupHorizontalMetrics(metrics)
builder.setupHorizontalHeader(ascent=800, descent=-200)
builder.setupNameTable({"familyName": "Raydiance Blocks", "styleName": "Regular"})
builder.setupOS2()
builder.setupPost()
kern = newTable("kern")
kern.version = 0
subtable = KernTable_format_0()
subtable.version, subtable.coverage, subtable.format = 0, 1, 0
subtable.kernTable = {("I", "O"): -50}
kern.kernTables = [subtable]
builder.font["kern"] = kern
builder.save("blocks.ttf")
