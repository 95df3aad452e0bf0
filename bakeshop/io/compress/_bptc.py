"""Tables of the BPTC formats (BC6H and BC7), from the Khronos Data Format Specification 1.4,
section 18 ("BPTC Compressed Texture Image Formats"), which Microsoft's "BC6H format" and "BC7
format" pages define identically.

The partition and anchor tables are the spec's tables bptcP2subset, bptcP3subset, bptcA2index,
bptcA32index and bptcA33index (partition p: the subset of texels 0..15 in row-major order). The
BC6H layouts are the spec's table-bptcblockformat in its own notation, least significant block
bit first: ``M5`` is five mode bits, ``R0[9:0]`` puts the next ten block bits into bits 0..9 of
endpoint R0 and ``R0[10:11]`` puts the next two into bits 11 then 10 (the spec's reversed runs).
Both were read out of the spec's source text by a script and checked against its per-bit tables
table-bptcbc6hbits and table-bptcbc6hbits2, which agree for all 14 modes and 82 bits.
"""

from __future__ import annotations

import re

import numpy as np


def _table(text: str) -> np.ndarray:
    """64 partitions written as 16 digits each (texels in row-major order) -> (64, 16) uint8."""
    rows = [list(map(int, word)) for word in text.split()]
    return np.array(rows, np.uint8)


#: subset (0, 1) of each texel for the 64 two-subset partitions.
PARTITIONS2 = _table(
    """
    0011001100110011 0001000100010001 0111011101110111 0001001100110111
    0000000100010011 0011011101111111 0001001101111111 0000000100110111
    0000000000010011 0011011111111111 0000000101111111 0000000000010111
    0001011111111111 0000000011111111 0000111111111111 0000000000001111
    0000100011101111 0111000100000000 0000000010001110 0111001100010000
    0011000100000000 0000100011001110 0000000010001100 0111001100110001
    0011000100010000 0000100010001100 0110011001100110 0011011001101100
    0001011111101000 0000111111110000 0111000110001110 0011100110011100
    0101010101010101 0000111100001111 0101101001011010 0011001111001100
    0011110000111100 0101010110101010 0110100101101001 0101101010100101
    0111001111001110 0001001111001000 0011001001001100 0011101111011100
    0110100110010110 0011110011000011 0110011010011001 0000011001100000
    0100111001000000 0010011100100000 0000001001110010 0000010011100100
    0110110010010011 0011011011001001 0110001110011100 0011100111000110
    0110110011001001 0110001100111001 0111111010000001 0001100011100111
    0000111100110011 0011001111110000 0010001011101110 0100010001110111
    """
)
#: subset (0, 1, 2) of each texel for the 64 three-subset partitions.
PARTITIONS3 = _table(
    """
    0011001102212222 0001001122112221 0000200122112211 0222002200110111
    0000000011221122 0011001100220022 0022002211111111 0011001122112211
    0000000011112222 0000111111112222 0000111122222222 0012001200120012
    0112011201120112 0122012201220122 0011011211221222 0011200122002220
    0001001101121122 0111001120012200 0000112211221122 0022002200221111
    0111011102220222 0001000122212221 0000001101220122 0000110022102210
    0122012200110000 0012001211222222 0110122112210110 0000011012211221
    0022110211020022 0110011020022222 0011012201220011 0000200022112221
    0000000211221222 0222002200120011 0011001200220222 0120012001200120
    0000111122220000 0120120120120120 0120201212010120 0011220011220011
    0011112222000011 0101010122222222 0000000021212121 0022112200221122
    0022001100220011 0220122102201221 0101222222220101 0000212121212121
    0101010101012222 0222011102220111 0002111200021112 0000211221122112
    0222011101110222 0002111211120002 0110011001102222 0000000021122112
    0110011022222222 0022001100110022 0022112211220022 0000000000002112
    0002000100020001 0222122202221222 0101222222222222 0111201122012220
    """
)
#: anchor texel of subset 1 of each two-subset partition.
ANCHOR2 = np.array(
    [
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        2,
        8,
        2,
        2,
        8,
        8,
        15,
        2,
        8,
        2,
        2,
        8,
        8,
        2,
        2,
        15,
        15,
        6,
        8,
        2,
        8,
        15,
        15,
        2,
        8,
        2,
        2,
        2,
        15,
        15,
        6,
        6,
        2,
        6,
        8,
        15,
        15,
        2,
        2,
        15,
        15,
        15,
        15,
        15,
        2,
        2,
        15,
    ],
    np.uint8,
)
#: anchor texel of subset 1 of each three-subset partition.
ANCHOR3_1 = np.array(
    [
        3,
        3,
        15,
        15,
        8,
        3,
        15,
        15,
        8,
        8,
        6,
        6,
        6,
        5,
        3,
        3,
        3,
        3,
        8,
        15,
        3,
        3,
        6,
        10,
        5,
        8,
        8,
        6,
        8,
        5,
        15,
        15,
        8,
        15,
        3,
        5,
        6,
        10,
        8,
        15,
        15,
        3,
        15,
        5,
        15,
        15,
        15,
        15,
        3,
        15,
        5,
        5,
        5,
        8,
        5,
        10,
        5,
        10,
        8,
        13,
        15,
        12,
        3,
        3,
    ],
    np.uint8,
)
#: anchor texel of subset 2 of each three-subset partition.
ANCHOR3_2 = np.array(
    [
        15,
        8,
        8,
        3,
        15,
        15,
        3,
        8,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        8,
        15,
        8,
        15,
        3,
        15,
        8,
        15,
        8,
        3,
        15,
        6,
        10,
        15,
        15,
        10,
        8,
        15,
        3,
        15,
        10,
        10,
        8,
        9,
        10,
        6,
        15,
        8,
        15,
        3,
        6,
        6,
        8,
        15,
        3,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        15,
        3,
        15,
        15,
        8,
    ],
    np.uint8,
)

#: BC6H block layouts, by mode number (the low 2 bits of the block if below 2, else its low 5).
BC6H_LAYOUTS = {
    0: (
        "M2 G2[4] B2[4] B3[4] R0[9:0] G0[9:0] B0[9:0] R1[4:0] G3[4] G2[3:0] G1[4:0] B3[0] "
        "G3[3:0] B1[4:0] B3[1] B2[3:0] R2[4:0] B3[2] R3[4:0] B3[3] PB[4:0]"
    ),
    1: (
        "M2 G2[5] G3[5:4] R0[6:0] B3[1:0] B2[4] G0[6:0] B2[5] B3[2] G2[4] B0[6:0] B3[3] B3[4:5] "
        "R1[5:0] G2[3:0] G1[5:0] G3[3:0] B1[5:0] B2[3:0] R2[5:0] R3[5:0] PB[4:0]"
    ),
    2: (
        "M5 R0[9:0] G0[9:0] B0[9:0] R1[4:0] R0[10] G2[3:0] G1[3:0] G0[10] B3[0] G3[3:0] B1[3:0] "
        "B0[10] B3[1] B2[3:0] R2[4:0] B3[2] R3[4:0] B3[3] PB[4:0]"
    ),
    6: (
        "M5 R0[9:0] G0[9:0] B0[9:0] R1[3:0] R0[10] G3[4] G2[3:0] G1[4:0] G0[10] G3[3:0] B1[3:0] "
        "B0[10] B3[1] B2[3:0] R2[3:0] B3[0] B3[2] R3[3:0] G2[4] B3[3] PB[4:0]"
    ),
    10: (
        "M5 R0[9:0] G0[9:0] B0[9:0] R1[3:0] R0[10] B2[4] G2[3:0] G1[3:0] G0[10] B3[0] G3[3:0] "
        "B1[4:0] B0[10] B2[3:0] R2[3:0] B3[2:1] R3[3:0] B3[3:4] PB[4:0]"
    ),
    14: (
        "M5 R0[8:0] B2[4] G0[8:0] G2[4] B0[8:0] B3[4] R1[4:0] G3[4] G2[3:0] G1[4:0] B3[0] "
        "G3[3:0] B1[4:0] B3[1] B2[3:0] R2[4:0] B3[2] R3[4:0] B3[3] PB[4:0]"
    ),
    18: (
        "M5 R0[7:0] G3[4] B2[4] G0[7:0] B3[2] G2[4] B0[7:0] B3[4:3] R1[5:0] G2[3:0] G1[4:0] "
        "B3[0] G3[3:0] B1[4:0] B3[1] B2[3:0] R2[5:0] R3[5:0] PB[4:0]"
    ),
    22: (
        "M5 R0[7:0] B3[0] B2[4] G0[7:0] G2[4:5] B0[7:0] G3[5] B3[4] R1[4:0] G3[4] G2[3:0] "
        "G1[5:0] G3[3:0] B1[4:0] B3[1] B2[3:0] R2[4:0] B3[2] R3[4:0] B3[3] PB[4:0]"
    ),
    26: (
        "M5 R0[7:0] B3[1] B2[4] G0[7:0] B2[5] G2[4] B0[7:0] B3[4:5] R1[4:0] G3[4] G2[3:0] "
        "G1[4:0] B3[0] G3[3:0] B1[5:0] B2[3:0] R2[4:0] B3[2] R3[4:0] B3[3] PB[4:0]"
    ),
    30: (
        "M5 R0[5:0] G3[4] B3[1:0] B2[4] G0[5:0] G2[5] B2[5] B3[2] G2[4] B0[5:0] G3[5] B3[3] "
        "B3[4:5] R1[5:0] G2[3:0] G1[5:0] G3[3:0] B1[5:0] B2[3:0] R2[5:0] R3[5:0] PB[4:0]"
    ),
    3: ("M5 R0[9:0] G0[9:0] B0[9:0] R1[9:0] G1[9:0] B1[9:0]"),
    7: ("M5 R0[9:0] G0[9:0] B0[9:0] R1[8:0] R0[10] G1[8:0] G0[10] B1[8:0] B0[10]"),
    11: ("M5 R0[9:0] G0[9:0] B0[9:0] R1[7:0] R0[10:11] G1[7:0] G0[10:11] B1[7:0] B0[10:11]"),
    15: ("M5 R0[9:0] G0[9:0] B0[9:0] R1[3:0] R0[10:15] G1[3:0] G0[10:15] B1[3:0] B0[10:15]"),
}

#: BC6H mode number -> (transformed endpoints, partition bits, endpoint bits, delta bits R, G, B),
#: the spec's table-bptcblockmodes.
BC6H_MODES = {
    0: (1, 5, 10, 5, 5, 5),
    1: (1, 5, 7, 6, 6, 6),
    2: (1, 5, 11, 5, 4, 4),
    6: (1, 5, 11, 4, 5, 4),
    10: (1, 5, 11, 4, 4, 5),
    14: (1, 5, 9, 5, 5, 5),
    18: (1, 5, 8, 6, 5, 5),
    22: (1, 5, 8, 5, 6, 5),
    26: (1, 5, 8, 5, 5, 6),
    30: (0, 5, 6, 6, 6, 6),
    3: (0, 0, 10, 10, 10, 10),
    7: (1, 0, 11, 9, 9, 9),
    11: (1, 0, 12, 8, 8, 8),
    15: (1, 0, 16, 4, 4, 4),
}

#: BC6H endpoint fields in layout order, then the partition number.
BC6H_FIELDS = ("R0", "G0", "B0", "R1", "G1", "B1", "R2", "G2", "B2", "R3", "G3", "B3", "PB")


def bc6h_bit_table() -> np.ndarray:
    """The layouts expanded to ``(32, 82, 2)`` int8: for each mode number and each of the block's
    first 82 bits, (field index in :data:`BC6H_FIELDS`, bit of that field); field -1 marks mode
    bits and bits past the layout (the index data)."""
    table = np.full((32, 82, 2), -1, np.int8)
    for mode, layout in BC6H_LAYOUTS.items():
        position = 0
        for token in layout.split():
            if token[0] == "M":
                position += int(token[1:])
                continue
            match = re.fullmatch(r"(\w\w)\[(\d+)(?::(\d+))?\]", token)
            assert match is not None, token  # the layouts above are constants of this form

            field, high, low = match[1], int(match[2]), int(match[3] or match[2])
            step = 1 if high >= low else -1
            for bit in range(low, high + step, step):
                table[mode, position] = (BC6H_FIELDS.index(field), bit)
                position += 1
    return table
