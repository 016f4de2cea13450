"""Error mapping: Rust errors arrive as ValueError / RuntimeError / OSError
subclasses with the Rust message; a Rust panic never crosses the boundary."""

import pytest

import framedyn as fd
from framedyn import _framedyn


def test_hierarchy():
    assert issubclass(fd.InvalidInputError, ValueError)
    assert issubclass(fd.InvalidInputError, fd.FramedynError)
    assert issubclass(fd.IntegrationError, RuntimeError)
    assert issubclass(fd.IntegrationError, fd.FramedynError)
    assert issubclass(fd.OutputError, OSError)
    assert issubclass(fd.InternalError, RuntimeError)


@pytest.mark.parametrize(
    "kind, cls",
    [("invalid", fd.InvalidInputError), ("integration", fd.IntegrationError), ("io", fd.OutputError), ("internal", fd.InternalError)],
)
def test_each_kind_maps_to_its_class(kind, cls):
    with pytest.raises(cls, match="the Rust message"):
        _framedyn._raise_for_test(kind, "the Rust message")


def test_panic_becomes_internal_error():
    with pytest.raises(fd.InternalError, match="Rust panic.*boom"):
        _framedyn._raise_for_test("panic", "boom")


def test_unknown_kind_is_invalid_input():
    with pytest.raises(fd.InvalidInputError, match="kind"):
        _framedyn._raise_for_test("nope", "x")


def test_integration_error_has_partial_default():
    e = fd.IntegrationError("x")
    assert e.partial is None
