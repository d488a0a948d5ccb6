"""What a run of a scene needs from the physics: the run backend, an explicit interface.

flexbearing.simulation.run drives a `RunBackend` and knows nothing else of the physics. Its parts,
with the calls the run makes (positional, always all of them):

    build_model(bearing, oil, options) -> model
    initial_state(model, speed_rad_s, Fa, Fr, load) -> y0           load: (Fx, Fy, Fz) at t = 0, N
    advance(model, y, t, t_next, speed_table, load_table, impacts, tol, h, ws[, max_step=...])
        -> (y, t, h, n_steps, n_rejected)                          integrate from t to t_next
        max_step (keyword, passed only when the scene sets integrator.max_step): the largest step, s
    evaluate_outputs(model, t, y, request, snapshot) -> {name: value}
        the quantities to record at the sample (t, y) for `request` (an OutputRequest), already
        selected (`select_recorded`); `snapshot` is what sample_snapshot took at the sample (None
        without one)
    advance_sampled (optional)(model, y, t, t_next, sample_times, speed_table, load_table, impacts,
                               tol, h, ws[, max_step=...])
        -> (y, t, h, n_steps, n_rejected, states at sample_times, snapshots at them)
        integrate across the samples without stopping at them (flexbearing.multibody.integrator, "Samples")
    sample_snapshot (optional)(model) -> snapshot
        what must be taken when a sample is reached, before the integration goes on (the flexible
        cage's stress peak-hold since the previous sample); the rest of a sample is a function of
        (t, y), evaluated later
    new_workspace (optional)(model, method) -> ws
        the integrator's workspace (its tableau and FSAL derivative, carried from one call to the
        next and stored with each checkpoint); without it ws is None and the backend integrates
        with its own method (the scene's integrator.method must be "dopri5")
    output_units: {name: SI unit} of outputs flexbearing.multibody.output_registry does not know
    file_attrs: attributes the results file carries for this backend (the reduced cage's file and hash)

`rigid_backend()` is the multibody model with a rigid cage; flexbearing.coupling.flexible_cage.backend
the flexible cage's. Tests pass a small stand-in physics of the same shape.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, NamedTuple

import numpy as np

from flexbearing.multibody import initial, integrator, model as mb, outputs
from flexbearing.multibody.output_registry import recorded_keys


class OutputRequest(NamedTuple):
    """What a run asks the backend to evaluate at each sample."""
    outputs: tuple                 # the scene's recorded output groups ([output] record)
    speed_table: np.ndarray        # the spectra (flexbearing.multibody.profiles)
    load_table: np.ndarray
    impacts: np.ndarray
    film: bool                     # film_thickness is recorded
    energy: bool                   # power_loss is recorded


@dataclass
class RunBackend:
    """The physics of a run (module docstring)."""
    build_model: Callable
    initial_state: Callable
    advance: Callable
    evaluate_outputs: Callable
    advance_sampled: Callable | None = None
    sample_snapshot: Callable | None = None
    new_workspace: Callable | None = None
    output_units: dict = field(default_factory=dict)
    file_attrs: dict = field(default_factory=dict)
    reduced_cage: Any = None       # the flexible cage's ReducedCage (None for a rigid cage)


def select_recorded(values: dict, request: OutputRequest) -> dict:
    """The evaluated `values` the request records (output_registry.recorded_keys), in their order."""
    return {k: values[k] for k in recorded_keys(request.outputs, values)}


def _evaluate_rigid(model, t, y, request: OutputRequest, snapshot=None) -> dict:
    values = outputs.evaluate_outputs(model, t, y, request.speed_table, request.load_table,
                                      request.impacts, film=request.film, energy=request.energy)
    return select_recorded(values, request)


def rigid_backend() -> RunBackend:
    """The multibody model with a rigid cage: model, quasi-static initial state, the adaptive
    integrator (flexbearing.multibody.integrator) and the outputs of flexbearing.multibody.outputs."""
    return RunBackend(build_model=mb.build_model, initial_state=initial.initial_state,
                      advance=integrator.advance, evaluate_outputs=_evaluate_rigid,
                      advance_sampled=integrator.advance_sampled, new_workspace=integrator.Workspace)
