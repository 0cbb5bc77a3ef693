"""The exceptions of :mod:`strand`.

Every message is the one the ``strand`` command line prints after ``error:``: it names
the case file (with ``line:column`` for a syntax error), the item (``rods[1]
'hose2'.length``) and a hint how to fix it. ``exit_code`` is the status the command
line exits with for the same failure.
"""

from __future__ import annotations


class StrandError(Exception):
    """Base class of Strand's errors (``strand`` exit status 1: I/O, internal)."""

    exit_code: int = 1


class InputError(StrandError, ValueError):
    """Invalid input: a case file that cannot be read or parsed, a failed validation,
    a bad change, variant or batch option, a hose starting inside a part (exit 2)."""

    exit_code = 2


class SolveError(StrandError, RuntimeError):
    """The solver could not start (exit 1)."""

    exit_code = 1


class NotConvergedError(SolveError):
    """A solve that did not converge where a converged one is required (exit 3):
    :meth:`strand.Result.check`, sensitivities of a case without an equilibrium."""

    exit_code = 3


class StrandWarning(UserWarning):
    """A warning of the command line (e.g. a warm start that fell back to a cold one)."""
