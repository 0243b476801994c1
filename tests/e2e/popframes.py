"""Frames for the popping tests (pop.sh, pop_sequence.sh), with the standard
library only: a textured background and a grating patch on it.

background(W, H): f(x, y) of a 160 x 120-style background, value noise of
4-pixel cells (seed 1), slightly yellow. patch(bg, a): f(x, y) of bg with a
24 x 24 square at (60, 40) modulated by 1 + a sin(2 pi x / 16). Import with
PYTHONPATH set to this folder.
"""
import math
import random


def background(W, H):
    rnd = random.Random(1)
    tex = [[0.35 + 0.25 * rnd.random() for _ in range(W // 4 + 1)] for _ in range(H // 4 + 1)]

    def bg(x, y):
        g = tex[y // 4][x // 4]
        return (g, g, 0.9 * g)
    return bg


def patch(bg, a):
    def f(x, y):
        r, g, b = bg(x, y)
        k = 1 + a * math.sin(2 * math.pi * x / 16) if 60 <= x < 84 and 40 <= y < 64 else 1
        return (r * k, g * k, b * k)
    return f
