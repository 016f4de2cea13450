"""Every public name of the package has a docstring that ``help()`` shows
(issue 9): functions, classes, their public methods, properties and
attributes (``__slots__`` dicts document attributes)."""

import inspect

import pytest

import framedyn as fd
import framedyn.ensemble
import framedyn.plot

MODULES = [fd, framedyn.plot, framedyn.ensemble]


def public_names():
    for mod in MODULES:
        names = getattr(mod, "__all__", None) or [n for n in dir(mod) if not n.startswith("_")]
        for n in names:
            obj = getattr(mod, n)
            if isinstance(obj, (str, tuple, list, dict, int, float)) or inspect.ismodule(obj):
                continue
            if getattr(obj, "__module__", "").split(".")[0] not in ("framedyn", ""):
                continue  # re-exported from elsewhere (typing, numpy)
            yield f"{mod.__name__}.{n}", obj
            if inspect.isclass(obj):
                for m, v in vars(obj).items():
                    if not m.startswith("_"):
                        yield f"{mod.__name__}.{n}.{m}", getattr(obj, m)


@pytest.mark.parametrize("name, obj", list(public_names()), ids=lambda v: v if isinstance(v, str) else "")
def test_public_name_has_a_docstring(name, obj):
    doc = inspect.getdoc(obj)
    assert doc and doc.strip(), f"{name} has no docstring"


def test_the_walk_covers_the_api():
    names = {n for n, _ in public_names()}
    for n in ("framedyn.solve", "framedyn.solve_batch", "framedyn.Stepper.step", "framedyn.Solution.data",
              "framedyn.Event.terminal", "framedyn.plot.path3d", "framedyn.ensemble.solve_ensemble"):
        assert n in names, n
