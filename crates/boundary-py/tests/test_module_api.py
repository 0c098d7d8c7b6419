"""What the module shows a user: ``dir(boundary_particles)`` lists the API and not the names
the module imports for its annotations, and the module docstring names every method."""

import typing

import boundary_particles as bp

# Names the package imports for its annotations besides `typing`'s own.
IMPORTED = {"annotations", "np", "ArrayLike", "NDArray", "PathLike", "_native"}


def test_dir_shows_the_api_and_no_typing_names():
    names = set(dir(bp))
    typing_names = {name for name in dir(typing) if not name.startswith("_")}
    leaked = sorted(names & (typing_names | IMPORTED))
    assert leaked == [], leaked
    for name in bp.__all__:
        assert name in names, name
        assert hasattr(bp, name), name


def test_the_module_docstring_names_every_method():
    doc = bp.__doc__ or ""
    missing = [m["name"] for m in bp.methods() if f"``{m['name']}``" not in doc]
    assert missing == [], missing
