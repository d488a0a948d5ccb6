"""The first elastic modes of a study variant's reduced cage, named by family: the cage study's
table of modes (flexbearing.studies.study).

The frequencies are those of the reduced cage file (flexbearing.fem_cage.reduced_cage, /modes:
the Craig–Bampton basis diagonalised, ascending, modes 0–5 rigid): Rayleigh–Ritz values of the
free–free cage, upper bounds of the FE frequencies (Craig & Kurdila, *Fundamentals of Structural
Dynamics*, 2006, §14.5). Each shape, the file's /modes/vertex_displacement at /mesh/vertices,
is named by flexbearing.fem_cage.classify (ring families after Rao, *Vibration of Continuous
Systems*, 2007, §11.4–11.5: in-plane bending/breathing, out-of-plane bending(-torsion),
torsion, local; n the circumferential wave number).

Only those three datasets are read (h5py slices): a reduced cage's stress modes run to hundreds
of megabytes, and the table needs none of them.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
import h5py
from flexbearing.fem_cage.classify import classify_mode

N_RIGID = 6                 # modes 0-5 of a reduced cage file are rigid (its schema)
N_TABLE = 6                 # elastic modes per variant in the study's table


class CageMode(NamedTuple):
    """One elastic mode of a variant's cage: number counted from 1 with the rigid ones (as Table 8
    and ADAMS count them), frequency (Hz), family and wave number n (None for rigid/local)."""
    mode: int
    frequency_hz: float
    family: str
    n: int | None


def cage_modes(reduced_cage_file, n_modes: int = N_TABLE) -> list[CageMode]:
    """The first `n_modes` elastic modes of the reduced cage file, classified."""
    with h5py.File(reduced_cage_file, "r") as f:
        freqs = np.asarray(f["modes/frequency_hz"][()], dtype=float)
        stop = min(len(freqs), N_RIGID + n_modes)
        X = np.asarray(f["mesh/vertices"][()], dtype=float)
        U = np.asarray(f["modes/vertex_displacement"][:, :, N_RIGID:stop], dtype=float)
    out = []
    for j in range(stop - N_RIGID):
        c = classify_mode(X, U[:, :, j], float(freqs[N_RIGID + j]))
        out.append(CageMode(N_RIGID + j + 1, float(freqs[N_RIGID + j]), c["family"],
                            None if c["family"] == "local" else c["n"]))
    return out


def mode_cell(m: dict) -> str:
    """'1234.5 Hz in-plane bending n=2' (a study.json entry of `cage_modes`)."""
    n = "" if m.get("n") is None else f" n={m['n']}"
    return f"{m['frequency_hz']:.1f} Hz {m['family']}{n}"
