"""The exception a library solver raises when it did not converge.

A library call that returns a state its solver did not converge to invites a caller to use it
unknowingly (issue 42: a test took a quasi-static state that had stopped half-way for the answer).
So the solvers raise by default and return only with `strict=False`, for callers that look at the
result's `converged` flag themselves (the command line, the scene layer, the studies).
"""
from __future__ import annotations


class SolverNotConverged(RuntimeError):
    """A solver stopped without meeting its tolerance.

    result: what the solver ended with (its own result type, `converged` False); residual: the
    solver's convergence measure when it stopped (scaled, as its docstring defines it); iterations:
    how many it made; diagnostic: why, in the engineer's terms."""

    def __init__(self, message: str, result=None, residual: float = float("nan"), iterations: int = 0,
                 diagnostic: str = ""):
        super().__init__(message)
        self.result = result
        self.residual = residual
        self.iterations = iterations
        self.diagnostic = diagnostic
