"""Every command's --help teaches: an Example: block, and a description for every option.

The commands are found by walking the click tree, so a command added later is checked too.
"""

from __future__ import annotations

import click
import pytest
from click.testing import CliRunner

from bakeshop.cli.main import cli


def tree(group: click.Group = cli, prefix: tuple[str, ...] = ()):
    """(words that run it, click command) for the root, every group and every command."""
    yield prefix, group
    ctx = click.Context(group)
    for name in group.list_commands(ctx):  # the root loads each command's module on request
        command = group.get_command(ctx, name)
        if isinstance(command, click.Group):
            yield from tree(command, (*prefix, name))
        else:
            yield (*prefix, name), command


COMMANDS = dict(tree())


@pytest.mark.parametrize("words", sorted(COMMANDS), ids=lambda w: " ".join(w) or "bakeshop")
def test_help_has_an_example_and_describes_every_option(words):
    result = CliRunner().invoke(cli, [*words, "--help"])
    assert result.exit_code == 0, result.output
    assert "Example:" in result.output
    bare = [
        "/".join(p.opts)
        for p in COMMANDS[words].params
        if isinstance(p, click.Option) and p.name != "help" and not (p.help or "").strip()
    ]
    assert bare == [], f"options without a description: {bare}"
