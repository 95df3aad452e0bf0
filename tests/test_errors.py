"""The error family: what the command line prints is the file and a plain reason."""

import pytest

from bakeshop.errors import ArgumentError, BakeshopError, FormatError, validate_choice


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
