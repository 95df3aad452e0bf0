"""The error family: what the command line prints is the file and a plain reason."""

import pytest

from bakeshop.errors import (
    ArgumentError,
    BakeshopError,
    FormatError,
    validate_choice,
    with_article,
)


def test_message_names_the_file():
    assert str(FormatError("truncated file", "probe.hdr")) == "probe.hdr: truncated file"
    assert str(BakeshopError("no file involved")) == "no file involved"


def test_family_is_also_value_error():
    assert issubclass(FormatError, ValueError) and issubclass(ArgumentError, BakeshopError)


def test_validate_choice_repeats_the_bad_value_and_the_choices():
    assert validate_choice("area", ("bilinear", "area"), "filter") == "area"
    with pytest.raises(
        ArgumentError, match=r"unknown filter 'cubic'; choose one of: bilinear, area"
    ):
        validate_choice("cubic", ("bilinear", "area"), "filter")


@pytest.mark.parametrize(
    "word, spoken",
    [
        ("angular", "an angular"),
        ("octahedral", "an octahedral"),
        ("OpenEXR", "an OpenEXR"),
        ("latlong", "a latlong"),
        ("mirrorball", "a mirrorball"),
        ("unit", "a unit"),
        ("HDR", "an HDR"),
        ("RG", "an RG"),
        ("BC6H", "a BC6H"),
        ("PFM", "a PFM"),
        (8, "an 8"),
        (11, "an 11"),
        (18, "an 18"),
        (110, "a 110"),
        (18000, "an 18000"),
        (800, "an 800"),
        (1024, "a 1024"),
        ("1.5", "a 1.5"),
    ],
)
def test_with_article_says_a_or_an_as_spoken(word, spoken):
    assert with_article(word) == spoken
