"""Bake recipes: a level's probes, normal maps, compressed textures and water described in one
TOML file, rebuilt incrementally, explained, and proven to load what they save.

- :mod:`bakeshop.bake.recipe`: the recipe file, validated completely before any work starts
  (:func:`load_recipe`), and a commented starter for a folder's files (:func:`starter_recipe`).
- :mod:`bakeshop.bake.operations`: what a step can do (:data:`OPERATIONS`: ``probe``,
  ``remap``, ``compress``, ``normals``, ``water``), with the options of the commands they mirror.
- :mod:`bakeshop.bake.build`: what to rebuild and why (:func:`plan`), the bake itself
  (:func:`run`), content digests cached by file stat, and the ``RECIPE.bake.json`` manifest holding
  every output's inputs, options, key and reload proof.
- :mod:`bakeshop.bake.manifest`: the manifest, digest cache and journal checked as untrusted
  input, and the proof that a file is the bake's own (the only files a bake replaces or
  deletes).

The command line is ``bakeshop bake RECIPE``; the same functions serve scripts (a DCC tool's
Python) with the same manifest and cache::

    from bakeshop.bake import load_recipe, run

    result = run(load_recipe("level.toml"))
    print(result.built, result.failed)
"""

from bakeshop.bake.build import BakeResult, Decision, plan, run, step_key
from bakeshop.bake.operations import OPERATIONS, Operation, Option
from bakeshop.bake.recipe import Recipe, Step, load_recipe, parse_recipe, starter_recipe

__all__ = [
    "OPERATIONS",
    "BakeResult",
    "Decision",
    "Operation",
    "Option",
    "Recipe",
    "Step",
    "load_recipe",
    "parse_recipe",
    "plan",
    "run",
    "starter_recipe",
    "step_key",
]
