"""bakeshop: the content pipeline of a real-time renderer.

HDR textures and their codecs (:mod:`bakeshop.io`), panoramas and cube maps
(:mod:`bakeshop.sphere`), what is computed from an environment (:mod:`bakeshop.light`),
normal-map compositing (:mod:`bakeshop.normals`) and buoyancy (:mod:`bakeshop.buoyancy`).
Every function takes and returns numpy arrays; :mod:`bakeshop.cli` is a thin shell on top.
"""

__version__ = "0.1.0"
