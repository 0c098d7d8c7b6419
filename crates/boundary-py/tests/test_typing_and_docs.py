"""The installed package's types and documentation: the stub of the compiled module agrees
with it (`mypy.stubtest`), the package type-checks against that stub (`mypy --strict`), every
public function shows its numpydoc docstring through `help()`, and the examples in the
docstrings run (doctest). mypy is a test dependency (`pip install boundary-particles[test]`;
`cargo xtask test` installs it)."""

import doctest
import pydoc
import subprocess
import sys

import boundary_particles as bp

PUBLIC = [
    bp.detect,
    bp.Detector,
    bp.Detector.detect,
    bp.auto_radius,
    bp.confusion,
    bp.score,
    bp.methods,
    bp.read,
    bp.write,
    bp.resample,
]


def run_mypy(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", *args], capture_output=True, text=True, check=False
    )


def test_the_stub_of_the_compiled_module_agrees_with_it():
    run = run_mypy("mypy.stubtest", "boundary_particles._native")
    assert run.returncode == 0, run.stdout + run.stderr


def test_the_package_type_checks_against_the_stub():
    run = run_mypy("mypy", "--strict", "-p", "boundary_particles")
    assert run.returncode == 0, run.stdout + run.stderr


def test_help_shows_the_numpydoc_docstrings():
    for item in PUBLIC:
        text = pydoc.render_doc(item, renderer=pydoc.plaintext)
        assert "Parameters\n" in text or "Returns\n" in text, item
        assert item.__doc__ and item.__doc__ in item.__doc__, item
    text = pydoc.render_doc(bp.detect, renderer=pydoc.plaintext)
    for section in ["Parameters", "Returns", "Raises", "points : array_like", "r : float or"]:
        assert section in text, section
    # The signature help() shows is the Python one, not the compiled module's.
    assert "method: 'str' = 'exact'" in text or "method: str = 'exact'" in text


def test_the_examples_in_the_docstrings_run():
    failures, tried = doctest.testmod(bp, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried >= 5 and failures == 0
