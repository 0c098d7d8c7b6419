"""PySPH's 2D dam break with the free surface labelled at every time step.

PySPH's own example (``pysph.examples.dam_break_2d``, WCSPH) with a ``boundary_particles``
tracker called in ``Application.post_step``: the fluid's labels are written into the particle
property ``boundary_label`` (1 on the free surface, 0 inside), which PySPH saves with every
output file and its viewer (``pysph view``) colours by. The tank's wall particles are given
to the tracker once, as fixed walls: after the first step they cost nothing.

The particles carry an id of our own, ``label_id`` (0 .. n-1 at creation): PySPH permutes
every property together when it re-sorts its arrays, so the id follows the particle, where
PySPH's ``gid`` is 4294967295 for every particle in a serial run and cannot serve.

Run (``pip install pysph boundary-particles``; PySPH needs a C compiler and Cython)::

    python examples/pysph/dam_break_2d.py --max-steps 300 -d /tmp/db2d
    python examples/pysph/dam_break_2d.py --dx 0.015 --max-steps 8000 -d /tmp/db2d_fine

The second is the size of the dam break in the docs (8978 fluid and 3256 wall particles,
``r = h = 0.0195``). PySPH 1.0b2's example gives its particles the mass and smoothing length
of its default ``dx = 0.03`` whatever ``--dx`` says (at ``--dx 0.015`` its positions then turn
NaN after about 60 steps); this example sets both from ``--dx`` (``m = dx^2 rho0``,
``h = hdx dx``), as the scheme's own ``h0`` already is. At ``--dx 0.015`` the collapse then
runs for about 10,000 steps (to t = 0.58 s) before PySPH's positions turn NaN; the tracker
stops the run there with a ``ValueError`` naming the particle.

Every option of PySPH's example applies (``--tf``, ``--openmp``, ``--pfreq``, ...). At the end
it prints the tracker's cost: its mean update time (wall clock, from gathering the positions
to storing the labels), PySPH's mean step time without it, and the ratio of the two, with the
mean share of particles the tracker recomputed, and writes it with the command, the date and
the machine to ``boundary_tracker_cost.txt`` in the output directory. Both are wall-clock
times: on a machine whose cores are busy with other work, the update's share also carries the
wait for the tracker's worker thread to be scheduled (and for the caller to be woken again),
which can exceed the update's own work (a few tenths of a millisecond here).
"""

import datetime
import os
import platform
import sys
import time

import numpy as np

import boundary_particles as bp
from pysph.examples.dam_break_2d import DamBreak2D, ro


class LabelledDamBreak2D(DamBreak2D):
    """The dam break, its fluid labelled in ``post_step``."""

    def create_particles(self):
        particles = super().create_particles()
        # PySPH 1.0b2's example gives every particle the mass and smoothing length of its
        # default dx = 0.03 whatever `--dx` says; set both from the spacing actually used, as
        # the scheme's own h0 = hdx * dx already is, so that a run is at the spacing it names.
        for array in particles:
            array.h[:] = self.h
            array.m[:] = self.dx**2 * ro
        fluid = self._named(particles, "fluid")
        fluid.add_property("boundary_label", type="int")
        fluid.add_property("label_id", type="long", data=np.arange(fluid.get_number_of_particles()))
        # A new list: `add_output_arrays` would extend the list the scheme shares between
        # the fluid and the walls, which have no such properties.
        fluid.set_output_arrays(list(fluid.output_property_arrays) + ["boundary_label", "label_id"])
        self.tracker = None
        self.update_seconds = 0.0
        self.updates = 0
        self.recomputed = 0
        self.started = None
        return particles

    @staticmethod
    def _named(particles, name):
        return next(pa for pa in particles if pa.name == name)

    def post_step(self, solver):
        fluid = self._named(self.particles, "fluid")
        start = time.perf_counter()
        if self.tracker is None:
            walls = self._named(self.particles, "boundary")
            # r = h, the smoothing length; the walls are fixed.
            self.tracker = bp.Tracker(
                h=self.h, walls=np.column_stack([walls.x, walls.y])
            )
        # PySPH's own coordinate arrays, read in place (no (n, 2) array built per step).
        labels = self.tracker.update(columns=(fluid.x, fluid.y), ids=fluid.label_id)
        fluid.boundary_label[:] = labels
        elapsed = time.perf_counter() - start
        if self.started is None:
            # The first update labels every particle; the steps are timed from the next.
            self.started = time.perf_counter()
            return
        self.update_seconds += elapsed
        self.updates += 1
        self.recomputed += self.tracker.recomputed

    def report(self):
        """The tracker's cost against PySPH's step, as printed at the end of a run."""
        if not self.updates:
            return "no step after the first: nothing to time"
        total = time.perf_counter() - self.started
        update = self.update_seconds / self.updates
        step = (total - self.update_seconds) / self.updates
        n = len(self._named(self.particles, "fluid").x)
        return (
            f"boundary_particles.Tracker: {self.updates} steps of {n} fluid particles: "
            f"update {1e3 * update:.3f} ms (wall clock, positions gathered to labels stored), "
            f"PySPH step {1e3 * step:.3f} ms without it, "
            f"ratio {update / step:.3f}; recomputed {100 * self.recomputed / (self.updates * n):.2f} % "
            "of the particles per step"
        )


if __name__ == "__main__":
    app = LabelledDamBreak2D()
    app.run()
    report = app.report()
    print(report)
    # The measurement, with what reproduces it.
    with open(os.path.join(app.output_dir, "boundary_tracker_cost.txt"), "w") as out:
        out.write(
            f"{report}\ncommand: python {' '.join(sys.argv)}\n"
            f"date: {datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')}\n"
            f"machine: {platform.node()}, {platform.machine()}, {os.cpu_count()} CPUs, "
            f"Python {platform.python_version()}\n"
        )
