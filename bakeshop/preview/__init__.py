"""See the bake: material balls, the golf course with DIM shadows, water, and probe transitions.

One set of GLSL shaders (:mod:`bakeshop.preview.glsl`) runs offscreen through moderngl
(:mod:`bakeshop.preview.render`, ``bakeshop preview``) and in the browser over WebGL2
(:mod:`bakeshop.preview.server`, ``bakeshop view``); :mod:`bakeshop.preview.reference` evaluates
the same equations in numpy at chosen pixels, and :mod:`bakeshop.preview.transitions` blends
probes along a camera path.

>>> from bakeshop.preview import Renderer, View, read_bake
>>> bake = read_bake("demo")                       # what bake-probe wrote
>>> with Renderer(bake) as r:
...     linear = r.render(View("golf", 1280, 720))  # (720, 1280, 4) float32 radiance
"""

from bakeshop.preview.bake import Bake, Sun, bake_exposure, bake_from_arrays, read_bake
from bakeshop.preview.render import DIFFUSE, SCENES, Renderer, View
from bakeshop.preview.scene import Camera, Golf, balls, default_camera, golf_course
from bakeshop.preview.transitions import (
    Walk,
    blend_bakes,
    influence_weights,
    path_weights,
    walk,
)

__all__ = [
    "DIFFUSE",
    "SCENES",
    "Bake",
    "Camera",
    "Golf",
    "Renderer",
    "Sun",
    "View",
    "Walk",
    "bake_exposure",
    "bake_from_arrays",
    "balls",
    "blend_bakes",
    "default_camera",
    "golf_course",
    "influence_weights",
    "path_weights",
    "read_bake",
    "walk",
]
