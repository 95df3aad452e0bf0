"""Small helpers shared by the command modules: argument types, option builders, input checks
and output safety.

**Every option and argument that holds a number has one of the types of this module**
(:class:`Number`, :class:`Integer`, :class:`Size`, :class:`Numbers`, :class:`Direction`,
:class:`Exposure`, :class:`MemorySize`): finite (NaN and the infinities are refused), within a
range that the option's ``--help`` states (click prints it: ``[default: 256; 1<=x<=4096]``), and
refused when parsed, in one line, before the command runs. The range is the one in which the
command makes sense; what a value inside it costs (memory, time) is estimated by the library
before it starts (:mod:`bakeshop.resources`). ``tests/cli/test_limits.py`` walks the command
tree and holds every command to this.

**Every file argument has a path type of this module**: inputs are checked when parsed
(:class:`bakeshop.cli._process.InputPath`), output names may hold braces only as the patterns
their command writes (:class:`OutputPath`: ``{face}``, ``{mip}``, ``{frame}``), and before a
command runs, no output may be (by name, symbolic or hard link, or pattern) one of its inputs
(:func:`refuse_overwriting_inputs`, run for every command by :func:`guard_outputs`).
"""

from __future__ import annotations

import functools
import glob
import math
import os
import re
import string
from pathlib import Path
from typing import NamedTuple

import click
import numpy as np

from bakeshop.cli._process import InputPath, record, recorded
from bakeshop.errors import ArgumentError
from bakeshop.io import stored_bits

# --- outputs that would overwrite inputs -----------------------------------------------------


def refuse_overwriting_inputs(output: str | os.PathLike, *inputs: str | os.PathLike) -> None:
    """Refuse, before any work, an ``output`` that would write over one of the command's inputs.

    ``output`` may be a pattern (``{face}``, ``{mip}``, ``{frame}``); the inputs are ``inputs``
    and every input the command was given (as recorded when its arguments were parsed: files,
    ``{face}`` sets, glob patterns). The output is refused when any file it may stand for *is*
    an input file: the same name, a symbolic link either way, a link through a directory, or a
    hard link (the same file on disk).

    Raises
    ------
    ArgumentError
        With the output file and the input it would overwrite.
    """
    text = os.fspath(output)
    targets = _existing_outputs(text)
    if not targets:
        return
    for typed in dict.fromkeys(
        [*(os.fspath(p) for p in inputs if p is not None), *recorded("inputs")]
    ):
        for source in _existing_inputs(typed):
            for target in targets:
                if _same_file(target, source):
                    raise ArgumentError(_overwrite_reason(text, target, typed, source), target)


def guard_outputs(group: click.Group) -> None:
    """Make every command of ``group`` (and of its sub-groups) call
    :func:`refuse_overwriting_inputs` on each of its :class:`OutputPath` arguments before it
    runs: a command gets the check by typing its outputs."""
    for command in group.commands.values():
        if isinstance(command, click.Group):
            guard_outputs(command)
        elif command.callback is not None and not hasattr(command.callback, "__guarded__"):
            command.callback = _guarded(command.callback)


def _guarded(callback):
    @functools.wraps(callback)
    def run(*args, **kwargs):
        for output in recorded("outputs"):
            refuse_overwriting_inputs(output)
        return callback(*args, **kwargs)

    run.__guarded__ = True
    return run


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _existing_inputs(typed: str) -> list[str]:
    """The existing files an input argument names: itself, its six ``{face}`` files (in both
    naming schemes), or its glob pattern's matches."""
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    if "{face}" in typed:
        names = [typed.replace("{face}", n) for n in (*FACE_NAMES, *FACE_NAMES_SHORT)]
    else:
        names = [typed, *(sorted(glob.glob(typed)) if glob.has_magic(typed) else ())]
    return [n for n in dict.fromkeys(names) if os.path.exists(n)]


def _existing_outputs(text: str) -> list[str]:
    """The existing files an output name may stand for: itself, or every file its patterns
    (:data:`PATTERNS`) may expand to."""
    parts = _pattern_parts(text)
    if not any(name for _, name, _ in parts):
        return [text] if os.path.exists(text) else []
    wildcard = "".join(glob.escape(literal) + ("*" if name else "") for literal, name, _ in parts)
    regex = re.compile(
        "".join(
            re.escape(literal) + (_field_regex(name, spec) if name else "")
            for literal, name, spec in parts
        )
    )
    return [p for p in sorted(glob.glob(wildcard)) if regex.fullmatch(p)]


def _field_regex(name: str, spec: str) -> str:
    from bakeshop.sphere import FACE_NAMES, FACE_NAMES_SHORT

    if name == "face":
        return "(?:" + "|".join((*FACE_NAMES, *FACE_NAMES_SHORT)) + ")"
    if not spec or re.fullmatch(r"0?[0-9]*d", spec):
        return "-?[0-9]+"
    return "[^/]+"


def _overwrite_reason(output: str, target: str, typed: str, source: str) -> str:
    notes = []
    if output != target:
        notes.append(f"the output {output} includes it")
    if typed != source:
        notes.append(f"the input {typed} includes it")
    if os.path.abspath(target) != os.path.abspath(source):
        if os.path.realpath(target) == os.path.realpath(source):
            notes.append(f"a symbolic link makes it the input {source}")
        else:
            notes.append(f"it is a hard link to the input {source}")
    return "refusing to write over the command's own input" + (
        f" ({'; '.join(notes)})" if notes else ""
    )


# --- output names: braces are patterns ----------------------------------------------------------

#: the patterns an output name may hold, each written by the commands that take it: six cube
#: faces, the levels of a mip chain, the frames of a sequence (with a format: {frame:04d}).
PATTERNS = {
    "face": "{face} (the six cube faces: posx ... negz)",
    "mip": "{mip} (the mip level: 0, 1, ...)",
    "frame": "{frame} (the frame: 0, 1, ...; {frame:04d} pads it)",
}


def _pattern_parts(text: str) -> list[tuple[str, str | None, str]]:
    """``(literal, field or None, format spec)`` pieces of an output name (no checks)."""
    try:
        return [(lit, name, spec or "") for lit, name, spec, _ in string.Formatter().parse(text)]
    except ValueError:
        return [(text, None, "")]


def check_output_name(text: str, allowed: tuple[str, ...] = ()) -> None:
    """Refuse an output name whose braces are not the patterns ``allowed`` (names of
    :data:`PATTERNS`): braces mark patterns and are never part of a file name; a format spec
    is allowed for ``{frame}`` only.

    Raises
    ------
    ArgumentError
        Naming the output, the brace that is wrong and the patterns the command writes.
    """
    what = (
        "braces in an output name mark the patterns "
        + " and ".join(PATTERNS[a] for a in allowed)
        + "; they cannot be part of a file name"
        if allowed
        else "this output is one file, and braces in an output name mark patterns: they "
        "cannot be part of a file name"
    )
    try:
        parts = list(string.Formatter().parse(text))
    except ValueError:
        raise ArgumentError(f"an unmatched '{{' or '}}': {what}", text) from None
    for literal, name, spec, conversion in parts:
        if "{" in literal or "}" in literal:  # '{{' or '}}'
            raise ArgumentError(f"a doubled brace: {what}", text)
        if name is None:
            continue
        field = (
            "{"
            + name
            + (f"!{conversion}" if conversion else "")
            + (f":{spec}" if spec else "")
            + "}"
        )
        if name not in allowed or conversion or (spec and name != "frame"):
            raise ArgumentError(f"{field} is not a pattern this command writes: {what}", text)
        if spec:
            try:
                format(0, spec)
            except ValueError as e:
                raise ArgumentError(f"{field}: {e}", text) from None


class OutputPath(click.Path):
    """An output file (or with ``directory``, a folder the command creates), whose name may hold
    the patterns ``fields`` (:data:`PATTERNS`) and no other brace (:func:`check_output_name`);
    remembered as one of the command's outputs, which :func:`guard_outputs` checks against its
    inputs before it runs."""

    def __init__(self, fields: tuple[str, ...] = (), *, directory: bool = False):
        super().__init__(
            dir_okay=directory, file_okay=not directory, writable=not directory, path_type=Path
        )
        self.fields = tuple(fields)
        self.directory = directory

    def convert(self, value, param, ctx):
        check_output_name(os.fspath(value), self.fields)
        path = super().convert(value, param, ctx)
        if not self.directory:
            record(ctx, "outputs", os.fspath(path))
        return path


def parse_size(text) -> tuple[int, int] | int:
    """Parse ``'WxH'`` into ``(width, height)`` or ``'N'`` into ``N`` (positive integers); a
    size already parsed (by :class:`Size`) is returned as it is."""
    if isinstance(text, (int, tuple)):
        return text
    try:
        parts = [int(p) for p in text.lower().split("x")]
    except ValueError:
        parts = []
    if len(parts) not in (1, 2) or min(parts) < 1:
        raise ArgumentError(f"invalid size {text!r}: expected N or WxH with positive integers")
    return parts[0] if len(parts) == 1 else (parts[0], parts[1])


#: click type for input files: a readable regular file (checked when parsed: a directory, named
#: pipe, device or symbolic link loop fails at once), remembered as one of the run's inputs.
INPUT = InputPath()
#: click type for an input environment: one file, or six named with {face} (checked on reading).
ENVIRONMENT = InputPath(patterns=True)
#: click type for input frames: files or glob patterns (each match checked on reading).
FRAMES = InputPath(patterns=True)
#: click type for an input image that may also be a .zarr store (a directory).
SOURCE = InputPath(stores=True)
#: click type for output files (one file: no brace in the name).
OUTPUT = OutputPath()
#: click type for an output environment: one file, or a cube's six files with {face}.
OUTPUT_FACES = OutputPath(("face",))
#: click type for an output mip chain: one container, or files with {mip} (and {face}).
OUTPUT_CHAIN = OutputPath(("mip", "face"))
#: click type for output frames: one file, or a sequence with {frame} ({frame:04d}).
OUTPUT_FRAMES = OutputPath(("frame",))
#: click type for an output directory (the commands create it when missing).
OUT_DIR = OutputPath(directory=True)


# --- numbers ------------------------------------------------------------------------------------

#: Largest side of an output image in pixels (a 65536 x 32768 latlong is 2^31 texels, 25 GB
#: of float32 RGB: past memory, where the chunked commands take over).
IMAGE_SIDE = 1 << 16


def _g(value) -> str:
    """A bound for people: ``4096``, ``0.001``, ``1e+06``."""
    return f"{value:g}" if isinstance(value, float) else str(value)


class Number(click.FloatRange):
    """A finite number in ``[low, high]`` (``low_open``/``high_open`` exclude an end), shown
    in ``--help`` as click shows a range. NaN is refused (click's :class:`click.FloatRange`
    lets it through, since every comparison with NaN is false), and so are the infinities
    unless ``allow_inf`` (where infinity means something: deep water). Both ends must be
    given unless ``allow_inf``: a number without an upper bound has no meaning for a
    command."""

    name = "number"

    def __init__(
        self,
        low: float,
        high: float | None,
        *,
        low_open: bool = False,
        high_open: bool = False,
        allow_inf: bool = False,
    ):
        if low is None or (high is None and not allow_inf):
            raise TypeError("a Number needs both bounds (an open upper bound needs allow_inf)")
        super().__init__(low, high, min_open=low_open, max_open=high_open)
        self.allow_inf = allow_inf

    def convert(self, value, param, ctx):
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if math.isnan(number) or (math.isinf(number) and not self.allow_inf):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        return super().convert(number, param, ctx)

    def _describe_range(self) -> str:
        low = f"{_g(float(self.min))}{'<' if self.min_open else '<='}"
        if self.max is None:
            return f"x{'>' if self.min_open else '>='}{_g(float(self.min))}"
        return f"{low}x{'<' if self.max_open else '<='}{_g(float(self.max))}"

    def describe_range(self) -> str:
        """The range as ``--help`` shows it: ``0<x<=1000``."""
        return self._describe_range()


class Integer(click.IntRange):
    """An integer in ``[low, high]`` (both required), shown in ``--help``."""

    name = "integer"

    def __init__(self, low: int, high: int):
        super().__init__(int(low), int(high))

    def describe_range(self) -> str:
        """The range as ``--help`` shows it: ``1<=x<=4096``."""
        return self._describe_range()


class Size(click.IntRange):
    """``N`` or ``WxH`` (with ``pair``): integers from ``low`` to ``high`` (each side); parsed
    to ``N`` or ``(W, H)``. ``--help`` states the range of each number."""

    name = "integer"

    def __init__(self, high: int = IMAGE_SIDE, *, pair: bool = True, low: int = 1):
        super().__init__(int(low), int(high))
        self.pair = pair

    def convert(self, value, param, ctx):
        if isinstance(value, (int, tuple)):
            return value
        parts = str(value).strip().lower().split("x")
        try:
            numbers = [int(p) for p in parts]
        except ValueError:
            numbers = []
        if not 1 <= len(numbers) <= (2 if self.pair else 1):
            wanted = "N or WxH" if self.pair else "N"
            self.fail(f"{value!r} is not a size: expected {wanted} (whole numbers)", param, ctx)
        numbers = [super(Size, self).convert(n, param, ctx) for n in numbers]
        return numbers[0] if len(numbers) == 1 else (numbers[0], numbers[1])

    def describe_range(self) -> str:
        """The range of each number, as ``--help`` shows it."""
        return self._describe_range()


class Numbers(Number):
    """``count`` numbers (any of ``count`` when it is a tuple; any number of them when None)
    separated by ``sep``, each a :class:`Number` in the range given: ``YAW,PITCH,ROLL``,
    ``UxV`` or ``T1,T2,...``. Parsed to a tuple of floats; one number stands for all of them
    when ``repeat`` (``4`` is ``4x4``); with ``fractions``, ``1/250`` is a number."""

    name = "numbers"

    def __init__(self, low, high, *, count=3, sep=",", repeat=False, fractions=False, **kwargs):
        super().__init__(low, high, **kwargs)
        self.counts = None if count is None else count if isinstance(count, tuple) else (count,)
        self.sep = sep
        self.repeat = repeat
        self.fractions = fractions

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        parts = str(value).strip().lower().split(self.sep)
        if self.counts is not None:
            counts = (*self.counts, 1) if self.repeat else self.counts
            if len(parts) not in counts:
                wanted = " or ".join(map(str, sorted(set(counts))))
                if param is not None and param.metavar:
                    wanted = f"{param.metavar}, {wanted}"
                self.fail(
                    f"{value!r}: expected {wanted} numbers separated by {self.sep!r}", param, ctx
                )
        numbers = tuple(
            super(Numbers, self).convert(self._number(p.strip(), param, ctx), param, ctx)
            for p in parts
        )
        if self.counts is not None and len(numbers) == 1 and self.repeat:
            return numbers * max(self.counts)
        return numbers

    def _number(self, text: str, param, ctx):
        if not self.fractions or "/" not in text:
            return text
        top, _, bottom = text.partition("/")
        try:
            return float(top) / float(bottom)
        except (ValueError, ZeroDivisionError, OverflowError):
            self.fail(f"{text!r} is not a number or a fraction like 1/250", param, ctx)


class Direction(Numbers):
    """A direction: ``+X``, ``-Y``, ``Z`` ... or ``x,y,z`` (finite, not all zero, each in
    [-1e6, 1e6]); parsed to a unit 3-tuple of floats."""

    name = "direction"
    _AXES = {"x": 0, "y": 1, "z": 2}

    def __init__(self):
        super().__init__(-1e6, 1e6, count=3)

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        m = re.fullmatch(r"\s*([+-]?)([xyz])\s*", str(value).lower())
        if m:
            axis = [0.0, 0.0, 0.0]
            axis[self._AXES[m[2]]] = -1.0 if m[1] == "-" else 1.0
            return tuple(axis)
        v = np.array(super().convert(value, param, ctx))
        length = float(np.linalg.norm(v))
        if length == 0:
            self.fail(
                f"{value!r} is not a direction: use +X, -X, +Y, -Y, +Z, -Z or x,y,z", param, ctx
            )
        return tuple(float(c) for c in v / length)


class Exposure(Number):
    """An exposure in stops (EV), finite and within ``[-64, 64]`` (2^64 spans any float32
    picture), or one of ``words`` (``auto``)."""

    name = "exposure"

    def __init__(self, words: tuple[str, ...] = ("auto",), limit: float = 64):
        super().__init__(-limit, limit)
        self.words = words

    def convert(self, value, param, ctx):
        if isinstance(value, str) and value.strip().lower() in self.words:
            return value.strip().lower()
        try:
            float(value)
        except (TypeError, ValueError):
            words = "".join(f" or {w!r}" for w in self.words)
            self.fail(f"{value!r} is not an exposure: a number of stops (EV){words}", param, ctx)
        return super().convert(value, param, ctx)


class Fields(click.ParamType):
    """Numbers separated by ``sep``, each of its own :class:`Number` type (``fields``, by
    name, in order), the first ``required`` of them needed: ``A:L[:DIR[:SPEED]]``. Parsed to
    a tuple of floats. ``--help`` must state :meth:`describe_range` (click cannot)."""

    name = "numbers"

    def __init__(self, fields: dict[str, Number], *, sep: str = ":", required: int = 1):
        self.fields = fields
        self.sep = sep
        self.required = required

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        parts = str(value).strip().split(self.sep)
        if not self.required <= len(parts) <= len(self.fields):
            self.fail(
                f"{value!r}: expected {self.sep.join(self.fields)} ({self.required} to "
                f"{len(self.fields)} numbers)",
                param,
                ctx,
            )
        out = []
        for (name, kind), text in zip(self.fields.items(), parts, strict=False):
            try:
                out.append(kind.convert(text.strip(), param, ctx))
            except click.BadParameter as e:
                self.fail(f"{name} in {value!r}: {e.message}", param, ctx)
        return tuple(out)

    def describe_range(self) -> str:
        """``amplitude 0<=x<=100, wavelength 0<x<=1e+04, ...``."""
        return ", ".join(f"{name} {kind.describe_range()}" for name, kind in self.fields.items())


class MemorySize(click.ParamType):
    """A memory bound: ``2GB``, ``1.5GiB``, ``512M`` (:func:`bakeshop.huge.memory.parse_memory`),
    at most 1 PB."""

    name = "size"
    #: the largest bound accepted (a petabyte).
    MAX = 10**15

    def convert(self, value, param, ctx):
        from bakeshop.huge.memory import parse_memory

        if isinstance(value, int):
            return value
        try:
            number = parse_memory(value)
        except ArgumentError as e:
            self.fail(e.reason, param, ctx)
        if number > self.MAX:
            self.fail(f"{value!r} is more than the limit of 1 PB", param, ctx)
        return str(value)

    def describe_range(self) -> str:
        """The range, as the option's help states it."""
        return "4 MiB to 1 PB"


def _parse_value(text: str):
    lowered = text.lower()
    if lowered in ("true", "yes", "on"):
        return True
    if lowered in ("false", "no", "off"):
        return False
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_options(pairs: tuple[str, ...]) -> dict:
    """``('compression=piz', 'bits=16')`` -> ``{'compression': 'piz', 'bits': 16}``."""
    options = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise ArgumentError(f"invalid option {pair!r}: expected KEY=VALUE")
        options[key.strip().replace("-", "_")] = _parse_value(value.strip())
    return options


def writer_option(help: str):
    """The repeatable ``-O/--option KEY=VALUE`` writer option (read with :func:`parse_options`)."""
    return click.option("-O", "--option", "options", multiple=True, metavar="KEY=VALUE", help=help)


def out_dir_option(help: str):
    """The ``--out-dir``/``-o`` option of commands that write a set of files."""
    return click.option("--out-dir", "-o", required=True, type=OUT_DIR, help=help)


def float_format_option(help: str):
    """The ``--format`` option (hdr, exr, pfm) of commands that write a set of float images."""
    return click.option(
        "--format",
        "fmt",
        type=click.Choice(("hdr", "exr", "pfm")),
        default="hdr",
        show_default=True,
        help=help,
    )


def convention_option(help: str):
    """The ``--convention`` option: the engine whose cube face set is read or written."""
    from bakeshop.sphere import CONVENTIONS

    return click.option(
        "--convention",
        type=click.Choice(CONVENTIONS),
        default="opengl",
        show_default=True,
        help=help,
    )


def is_ldr(path) -> bool:
    """True when ``path``'s format stores 8-bit display-encoded pictures (PNG, JPEG, TGA)."""
    from bakeshop.io import HDR_CODECS, codec_for

    return codec_for(path) not in HDR_CODECS


# -- pictures: the display rule, bit depth and display-encoded inputs -----------------------------


def warn(message: str, path=None) -> None:
    """One warning line on stderr: ``bakeshop: warning: FILE: message``."""
    where = f"{path}: " if path is not None else ""
    click.echo(f"bakeshop: warning: {where}{message}", err=True)


def _picture_cap(path) -> int:
    """The deepest samples a picture format stores: 16 for PNG, 8 for TGA and JPEG."""
    return 16 if Path(str(path)).suffix.lower() == ".png" else 8


def output_bits(
    path, *, requested: int | None = None, inputs=(), display: bool = False
) -> tuple[int, str | None]:
    """The sample depth of a picture file, and a one-line note when it is less than the inputs'.

    The depth follows the inputs: the deepest integer-stored input's (8 or 16); float inputs
    count as 16 for data (normals, linear values, values kept as stored) but not for a display
    picture (sRGB from HDR), which is 8-bit unless asked. ``requested`` (``--bits``, ``-O
    bits=``) wins. The format caps it (PNG 16, TGA and JPEG 8).

    Parameters
    ----------
    path : the output file
    requested : 8, 16 or None
    inputs : iterable of int or None
        :func:`bakeshop.io.stored_bits` of each input (None: float).
    display : bool
        The output is a display picture made from linear (HDR) values.

    Returns
    -------
    (bits, note)
        ``note`` is None unless precision is reduced below the inputs'.
    """
    inputs = list(inputs)
    integers = [b for b in inputs if b is not None]
    deepest = max(integers + ([] if display else [16] * (None in inputs)), default=8)
    cap = _picture_cap(path)
    if requested is not None:
        if requested not in (8, 16):
            raise ArgumentError(f"a picture has 8 or 16 bits per sample, not {requested!r}")
        if requested > cap:
            raise ArgumentError(f"{Path(str(path)).suffix} stores 8 bits: write .png for 16", path)
        bits = requested
    else:
        bits = min(deepest, cap)
    note = None
    if bits < deepest:
        why = "as asked" if requested is not None else f"{Path(str(path)).suffix} stores 8 bits"
        source = "float" if None in inputs and not integers else f"{deepest}-bit"
        note = f"written with 8 bits per sample ({why}); the input is {source}"
        if requested is None:
            note += ": write .png to keep 16"
    return bits, note


class PictureRule(NamedTuple):
    """The picture options of a command (:func:`picture_options`), parsed."""

    #: stops, or "auto" / "fit".
    ev: float | str
    #: "none", "reinhard" or "aces".
    operator: str
    #: True: skip the sRGB encoding.
    linear: bool
    #: triangular dither at 8 bits.
    dither: bool
    #: 8, 16, or None (follow the inputs).
    bits: int | None


def parse_exposure_mode(text: str | float) -> float | str:
    """A number of stops (finite, within +-64), ``'auto'`` or ``'fit'`` (as :class:`Exposure`
    parsed it, or text)."""
    from bakeshop.image import EXPOSURE_MODES, check_ev

    if isinstance(text, (int, float)):
        return check_ev(float(text))
    t = text.strip().lower()
    if t in EXPOSURE_MODES:
        return t
    try:
        return check_ev(t)
    except ArgumentError:
        raise ArgumentError(
            f"invalid exposure {text!r}: a number of stops in [-64, 64], 'auto' or 'fit'"
        ) from None


def picture_options(*, exposure: str = "0", operator: str = "none"):
    """The display rule's options, shared by every command that can write a picture from HDR
    data: ``--exposure``, ``--tonemap``, ``--linear``, ``--dither``, ``--bits``. The command
    receives them as one ``picture`` argument (a :class:`PictureRule`)."""
    import functools

    options = [
        click.option(
            "--exposure",
            "picture_exposure",
            type=Exposure(("auto", "fit")),
            default=exposure,
            show_default=True,
            metavar="EV|auto|fit",
            help="Picture outputs (.png .tga .jpg) from HDR data: exposure in stops, auto "
            "(log-average luminance of the valid texels to middle grey) or "
            "fit (only the brightest 0.1% clip).",
        ),
        click.option(
            "--tonemap",
            "picture_operator",
            type=click.Choice(("none", "reinhard", "aces")),
            default=operator,
            show_default=True,
            help="Picture outputs: tone curve after exposure (none clamps at 1).",
        ),
        click.option(
            "--linear",
            "picture_linear",
            is_flag=True,
            help="Picture outputs: store linear values (no sRGB encoding); 16-bit by default.",
        ),
        click.option(
            "--dither",
            "picture_dither",
            is_flag=True,
            help="Picture outputs at 8 bits: triangular dither of +-1 code value (seeded).",
        ),
        click.option(
            "--bits",
            "picture_bits",
            type=click.Choice(("8", "16")),
            help="Picture outputs: bits per sample. Default: the inputs' (16-bit stays "
            "16-bit); 8 for sRGB pictures of HDR data, 16 for linear ones; TGA and JPEG hold 8.",
        ),
    ]

    def decorate(command):
        @functools.wraps(command)
        def wrapper(*args, **kwargs):
            rule = PictureRule(
                parse_exposure_mode(kwargs.pop("picture_exposure")),
                kwargs.pop("picture_operator"),
                kwargs.pop("picture_linear"),
                kwargs.pop("picture_dither"),
                None if kwargs.get("picture_bits") is None else int(kwargs["picture_bits"]),
            )
            kwargs.pop("picture_bits")
            return command(*args, picture=rule, **kwargs)

        for option in reversed(options):
            wrapper = option(wrapper)
        return wrapper

    return decorate


class MadePicture(NamedTuple):
    """What :func:`make_picture` returns."""

    #: uint8 or uint16 code values.
    pixels: np.ndarray
    #: what was done, in one line (for the command's summary).
    line: str
    #: the line the file records (``description``).
    description: str
    #: the precision note, or None when nothing is lost.
    note: str | None
    #: the exposure applied, stops.
    ev: float


def make_picture(
    image, rule: PictureRule, target, *, weights=None, inputs=(), linear_input: bool = True
) -> MadePicture:
    """Apply the one display rule to ``image`` for the picture file ``target``.

    ``linear_input``: the values are linear (HDR, or decoded with --srgb-decode); they get
    exposure, tone curve, clamping and sRGB encoding (unless ``rule.linear``). Otherwise they
    are display-encoded values kept as stored (only clamped and quantised), and an exposure or
    tone curve asked for is refused. ``weights`` meter auto and fit exposure (an environment's
    solid angles, 0 where a texel does not count). ``inputs`` are the inputs'
    :func:`bakeshop.io.stored_bits`.

    Returns
    -------
    MadePicture
    """
    from bakeshop.image import to_picture

    if linear_input:
        encoding = "linear" if rule.linear else "srgb"
        bits, note = output_bits(
            target, requested=rule.bits, inputs=inputs, display=encoding == "srgb"
        )
        picture = to_picture(
            image,
            ev=rule.ev,
            operator=rule.operator,
            encoding=encoding,
            bits=bits,
            dither="triangular" if rule.dither else "none",
            weights=weights,
        )
        return MadePicture(picture.pixels, picture.describe(), picture.metadata(), note, picture.ev)
    if rule.ev != 0 or rule.operator != "none" or rule.linear:
        raise ArgumentError(
            "the input holds display-encoded values: --exposure, --tonemap and --linear apply "
            "to linear data (add --srgb-decode to linearise it first)"
        )
    bits, note = output_bits(target, requested=rule.bits, inputs=inputs)
    picture = to_picture(
        image, ev=0.0, encoding="linear", bits=bits, dither="triangular" if rule.dither else "none"
    )
    line = f"values kept as stored (display-encoded), {bits}-bit"
    return MadePicture(picture.pixels, line, f"bakeshop: {line}", note, 0.0)


def srgb_decode_option(command):
    """The ``--srgb-decode`` flag of commands that read radiance: linearise 8/16-bit input."""
    return click.option(
        "--srgb-decode",
        is_flag=True,
        help="An 8/16-bit input (.png .tga .jpg) holds sRGB-encoded values: decode them to "
        "linear light first (without it they are used as stored, with a warning).",
    )(command)


def linearise(image, path, metadata: dict, decode: bool) -> tuple[np.ndarray, bool]:
    """``(image, linear)``: an integer-stored input is sRGB-decoded when ``decode``, else kept
    as stored with one warning (its values are display-encoded, not radiance); ``decode`` on a
    float input is refused. Alpha is never decoded."""
    from bakeshop.image import srgb_decode

    integer = stored_bits(metadata) is not None
    if decode and not integer:
        raise ArgumentError("--srgb-decode applies to 8/16-bit inputs only", path)
    if not integer:
        return image, True
    if not decode:
        warn(
            f"{stored_bits(metadata)}-bit values are display-encoded (sRGB), not linear "
            "radiance; they are used as stored (--srgb-decode linearises them)",
            path,
        )
        return image, False
    out = np.array(image, dtype=np.float32)
    colour = 3 if out.shape[-1] >= 3 else out.shape[-1]
    out[..., :colour] = srgb_decode(out[..., :colour])
    return out, True


def is_picture(path) -> bool:
    """True when ``path`` (a ``{face}``/``{mip}`` pattern too) names picture files (PNG, TGA,
    JPEG); False for float formats and cube map containers."""
    from bakeshop.io import HDR_CODECS, codec_for
    from bakeshop.io.containers import is_container

    return not is_container(path) and codec_for(path) not in HDR_CODECS


def refuse_unused_picture_rule(rule: PictureRule, target) -> None:
    """Refuse picture options given for an output that is not a picture."""
    if rule.ev != 0 or rule.operator != "none" or rule.linear or rule.dither or rule.bits:
        raise ArgumentError(
            "--exposure, --tonemap, --linear, --dither and --bits apply to picture outputs "
            "(.png, .tga, .jpg); this output stores floats",
            target,
        )


def environment_weights(layout: str, spatial_shape, *, up=None) -> np.ndarray:
    """Metering weights of an environment: each texel's solid angle (0 outside the layout's
    valid texels: a disk's outside, a cross's empty cells), and 0 below the plane whose
    normal is ``up`` when given."""
    from bakeshop import sphere

    lay = sphere.layout("cube" if layout == "faces" else layout)
    weights = np.array(lay.solid_angles(tuple(spatial_shape)), dtype=np.float64)
    if up is not None:
        weights[sphere.texel_cosines(lay, tuple(spatial_shape), up) <= 0] = 0.0
    return weights


def write_any(target, image, rule: PictureRule, *, inputs=(), linear: bool, options=None):
    """Write ``image`` to ``target`` by the one rule: a picture file through
    :func:`make_picture` (its precision note warned), a float file with the rule's exposure
    only (a number of stops, or auto/fit metered on the frame). Returns the line saying what
    was done to the values, or None when they were written as they are."""
    from bakeshop.image import choose_exposure, exposure
    from bakeshop.io import write_image

    options = dict(options or {})
    if is_picture(target):
        requested = options.pop("bits", None)
        if requested is not None and rule.bits is not None and requested != rule.bits:
            raise ArgumentError("--bits and -O bits= disagree", target)
        if requested is not None:
            rule = rule._replace(bits=int(requested))
        made = make_picture(image, rule, target, inputs=inputs, linear_input=linear)
        write_image(target, made.pixels, description=made.description, **options)
        if made.note:
            warn(made.note, target)
        return made.line
    if rule.operator != "none" or rule.linear or rule.dither or rule.bits:
        raise ArgumentError(
            "--tonemap, --linear, --dither and --bits apply to picture outputs (.png, .tga, "
            ".jpg); this output stores floats",
            target,
        )
    if rule.ev == 0:
        write_image(target, image, **options)
        return None
    chosen = choose_exposure(image, rule.ev)
    write_image(target, exposure(image, chosen.ev), **options)
    return f"exposure {chosen.ev:+.2f} EV" + ("" if chosen.mode == "fixed" else f" ({chosen.mode})")
