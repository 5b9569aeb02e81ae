"""The package's surface: docstrings everywhere, the exception hierarchy, typing marker."""

import inspect
import pathlib

import tocsin


def test_every_public_name_has_a_docstring():
    missing = []
    for name in tocsin.__all__:
        obj = getattr(tocsin, name)
        if not (obj.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(obj):
            for attr, value in vars(obj).items():
                if not attr.startswith("_") and not (getattr(value, "__doc__", None) or "").strip():
                    missing.append(f"{name}.{attr}")
    assert missing == []


def test_exception_hierarchy():
    for cls in (tocsin.MeshError, tocsin.MeshFileError, tocsin.PoseError, tocsin.MotionError, tocsin.OptionsError):
        assert issubclass(cls, tocsin.TocsinError)
        assert issubclass(cls, ValueError)
    assert issubclass(tocsin.MeshFileError, OSError)
    assert issubclass(tocsin.TocsinError, Exception)


def test_typed_package():
    root = pathlib.Path(tocsin.__file__).parent
    assert (root / "py.typed").exists() and (root / "_core.pyi").exists()
