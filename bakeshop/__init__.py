"""bakeshop: the content pipeline of a real-time renderer.

HDR textures and their codecs (:mod:`bakeshop.io`), panoramas and cube maps
(:mod:`bakeshop.sphere`), what is computed from an environment (:mod:`bakeshop.light`),
normal-map compositing (:mod:`bakeshop.normals`) and buoyancy (:mod:`bakeshop.buoyancy`).
Every function takes and returns numpy arrays; :mod:`bakeshop.cli` is a thin shell on top.
"""

from bakeshop._kernel_stamps import install as _stamp_kernels

__version__ = "0.1.0"

_stamp_kernels()  # numba's cache keyed on each kernel's import closure, not its file alone
