"""What a step solves with: the elastic problem of one mesh, factorised,
and its contact problem; `solve(load factor)` gives the displacement with
the active set on the faces that have contact rows.

How it factorises is the solver's choice; a step sees none of it:

- dense or saddle: up to DENSE_ROWS pair rows the contact problem works on
  the dense pair compliance (MUMPS's Schur complement on the pair dofs);
  above, each set of contact states is one sparse saddle-point system
  (fem.pair_saddle), and K alone is never factorised;
- far-field condensation: on a mesh with a patch (propagation.patch) the
  cells outside it are condensed once (fem.far_field) and that
  factorisation is kept for the next steps whose far field is the same: a
  step then factorises its patch only (not with pieces that only contact
  holds, nor in the saddle route, whose gauges and rows the far field does
  not know);
- deferred expansion: after a condensed solve the displacement inside the
  far field is computed only when something reads it there
  (ElasticProblem.expand);
- the solution span: a right-hand side in the span of kept ones is answered
  by their solutions' combination, with no solve (fem.solution_span).
"""
from __future__ import annotations

from . import progress
from .errors import ComputationError
from .fem.contact_problem import ContactProblem
from .fem.elasticity import ElasticProblem
from .fem.far_field import FarField
from .fem.pair_operator import PairOperator

#: pair systems of more rows than this are solved as sparse saddle-point systems (fem.pair_saddle):
#: the dense route's pair compliance (m^2 numbers for m rows) and MUMPS's dense Schur complement on the
#: pair dofs (4 dofs a pair: (2 m)^2 numbers where each pair has two rows, 0.8 GB of doubles at this m)
#: grow with the square of the rows
DENSE_ROWS = 5000


class Solver:
    """problem: the elastic problem (fem.elasticity.ElasticProblem,
    assembled and factorised); contact: its contact problem
    (fem.contact_problem.ContactProblem); far: the far field's factorisation
    it used (fem.far_field.FarField), or None; solved_at: the load factor
    of the last solve."""

    def __init__(self, problem, contact, far=None):
        self.problem, self.contact, self.far = problem, contact, far
        self.solved_at: float | None = None

    @classmethod
    def factorised(cls, fm, cm, material, loads, rows, floating, far, timer) -> Solver:
        """The problem of the DOLFINx mesh `fm` (of the crack mesh `cm`)
        under `loads`, with the contact rows `rows` and the pieces only
        contact holds (`floating`, wingcrack.floating.Floating, or None),
        assembled and factorised. far: the far field factorised at an earlier
        step (or None): used where this mesh's far field is its, else a new
        one is factorised where the mesh has a far field; the one used is
        Solver.far (the caller destroys the old one when it changes).
        timer: step.Timer, lapped by phase."""
        saddle = len(rows) > DENSE_ROWS
        if saddle and floating is not None:
            raise ComputationError(f"pieces that only contact holds in a pair system of {len(rows)} rows: their "
                                   f"rigid modes need the dense pair problem, which holds at most {DENSE_ROWS} rows")
        timer.lap("assemble")
        if far is not None and (floating is not None or saddle or not far.matches(cm)):
            far = None   # the patch moved on, or a gauge changed its supports (the caller destroys the old one)
        timer.lap("patch")
        # with the far field kept, K is assembled where the reduced factorisation reads it only
        problem = ElasticProblem(fm, material.E, material.nu, material.plane, loads, cm=cm,
                                 far_interior=None if far is None else far.interior_of(cm))
        timer.lap("assemble")
        started = False
        if far is None and cm.far is not None and floating is None and not saddle:
            far = FarField.start(problem, cm)
            started = far is not None
        timer.lap("patch")
        if not saddle:   # the saddle-point route factorises K with the contact rows, K alone never
            progress.doing(f"factorising the stiffness ({fm.num_dofs} DOFs, {len(rows)} pair rows)")
            problem.factorize(schur_dofs=PairOperator.pair_dofs(fm, rows) if len(rows) else None, far=far)
        timer.lap("factorize")
        if far is not None and not problem.reused_far:   # other supports in the far field: factorised whole
            if started:
                far.destroy()
            far = None
        cm.stats["far_field"] = None if far is None else ("factorised" if started else "reused")
        return cls(problem, ContactProblem(problem, rows, floating, saddle=saddle), far)

    def solve(self, load_factor: float):
        """Displacement at `load_factor`, with contact (the active set) on the
        faces that have it, friction as one increment from the reference
        slip (see accept); the contact result (None without rows)."""
        self.solved_at = float(load_factor)
        return self.contact.solve(load_factor)

    def solution_at(self, load_factor: float):
        """The solution at `load_factor`: the last solve's where it was at
        this load factor, else a new solve (the contact result). The same:
        nothing but a solve changes the state a solve starts from, or
        accept(), which takes the last solve's own solution, whose increment
        to the same load is none."""
        if self.solved_at != float(load_factor):
            return self.solve(load_factor)
        return self.contact.result

    def accept(self) -> None:
        """The current solution becomes the converged state the next solve
        starts from (friction is path dependent; without it nothing changes)."""
        self.contact.accept()

    def release(self) -> None:
        """Free the MUMPS factors now (tens of MB a step)."""
        self.problem.destroy()
        if getattr(self.contact, "saddle", None) is not None:
            self.contact.saddle.destroy()
