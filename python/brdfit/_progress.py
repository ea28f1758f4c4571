"""Progress reports: brdfit.Progress, made from the library's bf_progress_report."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, Optional

from ._brdfit import ffi, lib


@dataclass(frozen=True)
class Progress:
    """Where a fit, comparison or selection is: what progress= receives (docs/api.md,
    "Progress and cancelling").

    phase: the fit's step, in this order: "candidates" (random starts scored on the
    screening set), "screen" (the chosen starts solved there), "presolve" (starts solved
    on the presolve's subsample), "data" (solves on all samples), then "done" once, when
    the fit has ended (cost: its final cost). start of starts: the phase's solve (or
    candidate) and how many it runs at most; iteration and cost within the solve;
    samples: the size of the set the solve uses. model: the spec being fitted (in select,
    the candidate). material: in compare, the index of the sample set in samples_list
    (None otherwise). fold: 1 to K for the fits of a cross-validation (rank="cv"), else 0."""

    phase: str
    start: int
    starts: int
    iteration: int
    cost: float
    samples: int
    model: str
    material: Optional[int] = None
    fold: int = 0


_phase_names: Dict[int, str] = {}


def _phase_name(phase: int) -> str:
    name = _phase_names.get(phase)
    if name is None:  # the library's names, asked once each
        name = _phase_names[phase] = ffi.string(lib.bf_fit_phase_name(phase)).decode()
    return name


def _progress_of(r: Any) -> Progress:
    """A Progress of the library's report r (read during the callback: its texts are the
    library's for that call only)."""
    return Progress(phase=_phase_name(r.phase), start=int(r.start), starts=int(r.starts),
                    iteration=int(r.iteration), cost=float(r.cost), samples=int(r.samples),
                    model=ffi.string(r.spec).decode("utf-8", "surrogateescape") if r.spec != ffi.NULL else "",
                    material=int(r.material) if r.material >= 0 else None, fold=int(r.fold))
