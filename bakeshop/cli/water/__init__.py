"""``bakeshop water``: looping ocean textures, impact ripples and underwater murk constants.

One module per subcommand (:mod:`.ocean`, :mod:`.ripples`, :mod:`.murk`), each adding its
command to the group of :mod:`._group`; :mod:`._sets` writes the texture sets they share.
"""

from __future__ import annotations

import click

from bakeshop.cli.water import murk, ocean, ripples
from bakeshop.cli.water._group import water

#: the subcommand modules: importing each adds its command to the group.
SUBCOMMANDS = (ocean, ripples, murk)


def register(group: click.Group) -> None:
    """Add the ``water`` command group to the ``bakeshop`` command."""
    group.add_command(water)
