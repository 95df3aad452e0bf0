"""Small helpers shared by the command modules: option builders, the display rule for
pictures, bit depths and display-encoded inputs. Path types and output safety live in
:mod:`bakeshop.cli._paths`, number types in :mod:`bakeshop.cli._numbers`."""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any, NamedTuple, TypeVar

import click
import numpy as np
from numpy.typing import ArrayLike

from bakeshop.cli._numbers import Exposure
from bakeshop.cli._paths import OUT_DIR
from bakeshop.errors import ArgumentError
from bakeshop.io import stored_bits

#: a command callback, returned unchanged by the option builders.
F = TypeVar("F", bound=Callable[..., Any])


def parse_options(pairs: tuple[str, ...]) -> dict[str, str]:
    """``('compression=piz', 'bits=16')`` -> ``{'compression': 'piz', 'bits': '16'}``: the
    values stay text, converted and checked by the codec's signature
    (:func:`bakeshop.io.write_image`), so ``rle=maybe`` is refused, never taken as true."""
    options: dict[str, str] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise ArgumentError(f"invalid option {pair!r}: expected KEY=VALUE")
        options[key.strip().replace("-", "_")] = value.strip()
    return options


def picture_bits(value: object, path: str | os.PathLike | None = None) -> int:
    """8 or 16, from ``--bits`` or ``-O bits=`` (text or a number)."""
    bits = {"8": 8, "16": 16}.get(str(value).strip())
    if bits is None:
        raise ArgumentError(f"a picture has 8 or 16 bits per sample, not {value!r}", path)
    return bits


def writer_option(help: str) -> Callable[[F], F]:
    """The repeatable ``-O/--option KEY=VALUE`` writer option (read with :func:`parse_options`)."""
    return click.option("-O", "--option", "options", multiple=True, metavar="KEY=VALUE", help=help)


def out_dir_option(help: str) -> Callable[[F], F]:
    """The ``--out-dir``/``-o`` option of commands that write a set of files."""
    return click.option("--out-dir", "-o", required=True, type=OUT_DIR, help=help)


def float_format_option(help: str) -> Callable[[F], F]:
    """The ``--format`` option (hdr, exr, pfm) of commands that write a set of float images."""
    return click.option(
        "--format",
        "fmt",
        type=click.Choice(("hdr", "exr", "pfm")),
        default="hdr",
        show_default=True,
        help=help,
    )


def convention_option(help: str) -> Callable[[F], F]:
    """The ``--convention`` option: the engine whose cube face set is read or written."""
    from bakeshop.sphere import CONVENTIONS

    return click.option(
        "--convention",
        type=click.Choice(CONVENTIONS),
        default="opengl",
        show_default=True,
        help=help,
    )


def is_ldr(path: str | os.PathLike) -> bool:
    """True when ``path``'s format stores 8-bit display-encoded pictures (PNG, JPEG, TGA); a
    texture container (.dds, .ktx, .ktx2) holds the values a GPU samples, so never."""
    from bakeshop.io import HDR_CODECS, codec_for
    from bakeshop.io.containers import is_container

    return not is_container(path) and codec_for(path) not in HDR_CODECS


# -- pictures: the display rule, bit depth and display-encoded inputs -----------------------------


def warn(message: str, path: str | os.PathLike | None = None) -> None:
    """One warning line on stderr: ``bakeshop: warning: FILE: message``."""
    where = f"{path}: " if path is not None else ""
    click.echo(f"bakeshop: warning: {where}{message}", err=True)


def _picture_cap(path: str | os.PathLike) -> int:
    """The deepest samples a picture format stores: 16 for PNG, 8 for TGA and JPEG."""
    return 16 if Path(str(path)).suffix.lower() == ".png" else 8


def output_bits(
    path: str | os.PathLike,
    *,
    requested: int | None = None,
    inputs: Iterable[int | None] = (),
    display: bool = False,
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


def picture_options(
    *, exposure: str = "0", operator: str = "none"
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """The display rule's options, shared by every command that can write a picture from HDR
    data: ``--exposure``, ``--tonemap``, ``--linear``, ``--dither``, ``--bits``. The command
    receives them as one ``picture`` argument (a :class:`PictureRule`)."""
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

    def decorate(command: Callable[..., Any]) -> Callable[..., Any]:
        @functools.wraps(command)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
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
    image: np.ndarray,
    rule: PictureRule,
    target: str | os.PathLike,
    *,
    weights: np.ndarray | None = None,
    inputs: Iterable[int | None] = (),
    linear_input: bool = True,
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


def srgb_decode_option(command: F) -> F:
    """The ``--srgb-decode`` flag of commands that read radiance: linearise 8/16-bit input."""
    return click.option(
        "--srgb-decode",
        is_flag=True,
        help="An 8/16-bit input (.png .tga .jpg) holds sRGB-encoded values: decode them to "
        "linear light first (without it they are used as stored, with a warning).",
    )(command)


def linearise(
    image: np.ndarray, path: str | os.PathLike, metadata: dict, decode: bool
) -> tuple[np.ndarray, bool]:
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


#: formats that store colour without alpha (Radiance, PFM, JPEG).
RGB_ONLY = (".hdr", ".pic", ".rgbe", ".pfm", ".jpg", ".jpeg")


def rgb_only(*targets: str | os.PathLike | None) -> list[str | os.PathLike]:
    """The ``targets`` whose format stores RGB only (:data:`RGB_ONLY`)."""
    return [t for t in targets if t is not None and Path(t).suffix.lower() in RGB_ONLY]


def alpha_option(command: F) -> F:
    """The ``--alpha`` option of every command that may write an RGB-only format (.hdr, .pfm,
    .jpg) from an input with alpha; the command passes it to :func:`fit_alpha`."""
    return click.option(
        "--alpha",
        type=click.Choice(("drop", "premultiply")),
        help="An input's alpha channel when an output stores RGB only (.hdr, .pfm, .jpg): drop "
        "it, or multiply the colour by it first. An alpha of 1 everywhere (as OpenEXR files "
        "often carry) is dropped with a note; any other alpha is refused without this option.",
    )(command)


def fit_alpha(
    image: np.ndarray,
    how: str | None,
    source: str | os.PathLike,
    *targets: str | os.PathLike | None,
    note: bool = True,
) -> np.ndarray:
    """``image`` ((..., C) array) with its alpha made fit for ``targets``: unchanged when it has
    no alpha or every target stores alpha; else an alpha of 1 everywhere is dropped (with a
    ``note`` on stdout), and any other alpha is dropped or premultiplied as ``how`` says, or
    refused.

    Raises
    ------
    ArgumentError
        A non-constant alpha, an RGB-only target and no ``how``: naming ``--alpha``.
    """
    outputs = rgb_only(*targets)
    if image.shape[-1] != 4 or not outputs:
        return image
    suffix = Path(outputs[0]).suffix
    alpha = image[..., 3:]
    if how == "premultiply":
        return image[..., :3] * alpha
    if how is None and not np.all(alpha == 1):
        raise ArgumentError(
            f"the input's alpha is not 1 everywhere and {suffix} stores RGB only: choose "
            "--alpha drop or --alpha premultiply (or write .exr, .png or .tif)",
            outputs[0],
        )
    if how is None and note:
        click.echo(f"{source}: alpha (1 everywhere) dropped: {suffix} stores RGB only")
    return np.ascontiguousarray(image[..., :3])


def is_picture(path: str | os.PathLike) -> bool:
    """True when ``path`` (a ``{face}``/``{mip}`` pattern too) names picture files (PNG, TGA,
    JPEG); False for float formats and cube map containers."""
    from bakeshop.io import HDR_CODECS, codec_for
    from bakeshop.io.containers import is_container

    return not is_container(path) and codec_for(path) not in HDR_CODECS


def refuse_unused_picture_rule(rule: PictureRule, target: str | os.PathLike) -> None:
    """Refuse picture options given for an output that is not a picture."""
    if rule.ev != 0 or rule.operator != "none" or rule.linear or rule.dither or rule.bits:
        raise ArgumentError(
            "--exposure, --tonemap, --linear, --dither and --bits apply to picture outputs "
            "(.png, .tga, .jpg); this output stores floats",
            target,
        )


def environment_weights(
    layout: str, spatial_shape: tuple[int, ...], *, up: ArrayLike | None = None
) -> np.ndarray:
    """Metering weights of an environment: each texel's solid angle (0 outside the layout's
    valid texels: a disk's outside, a cross's empty cells), and 0 below the plane whose
    normal is ``up`` when given."""
    from bakeshop import sphere

    lay = sphere.layout("cube" if layout == "faces" else layout)
    weights = np.array(lay.solid_angles(tuple(spatial_shape)), dtype=np.float64)
    if up is not None:
        weights[sphere.texel_cosines(lay, tuple(spatial_shape), up) <= 0] = 0.0
    return weights


def write_any(
    target: str | os.PathLike,
    image: np.ndarray,
    rule: PictureRule,
    *,
    inputs: Iterable[int | None] = (),
    linear: bool,
    options: dict[str, Any] | None = None,
) -> str | None:
    """Write ``image`` to ``target`` by the one rule: a picture file through
    :func:`make_picture` (its precision note warned), a float file with the rule's exposure
    only (a number of stops, or auto/fit metered on the frame). Returns the line saying what
    was done to the values, or None when they were written as they are."""
    from bakeshop.image import choose_exposure, exposure
    from bakeshop.io import write_image

    options = dict(options or {})
    if is_picture(target):
        requested = options.pop("bits", None)
        if requested is not None:
            requested = picture_bits(requested, target)
            if rule.bits is not None and requested != rule.bits:
                raise ArgumentError("--bits and -O bits= disagree", target)
            rule = rule._replace(bits=requested)
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
