#!/usr/bin/python3
"""Distributed weights from Python (docs/distributed.md): run with

    mpirun -np 2 /usr/bin/python3 python/examples/distributed_weights.py CAGE MODEL METHOD

Every process takes its share of the model's points (numpy's array_split) and computes their
weights with barylab.weights(): with VTK's MPI controller set as the global controller, the
filter solves the mesh-based methods once (process 0) and sends the mesh weights to the
others. The check: every process's rows equal the serial run's (computed first, before the
controller is set), bitwise for mean value, harmonic, BBW, LBC and Green coordinates."""
import sys

from mpi4py import MPI  # initialises MPI first (vtkMPIController.Initialize() needs it)
import numpy as np
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.vtkParallelMPI import vtkMPIController

import barylab


def main(cage_path, model_path, method):
    cage = barylab.read(cage_path)
    points = barylab.points_of(barylab.read(model_path))
    serial = barylab.weights(points, cage, method=method)  # no controller yet: one process

    controller = vtkMPIController()
    controller.Initialize()
    vtkMultiProcessController.SetGlobalController(controller)
    rank, count = controller.GetLocalProcessId(), controller.GetNumberOfProcesses()
    rows = np.array_split(np.arange(len(points)), count)[rank]
    piece = barylab.weights(points[rows], cage, method=method)  # shares the per-cage work
    difference = float(np.abs(piece - serial[rows]).max()) if len(rows) else 0.0
    worst = MPI.COMM_WORLD.allreduce(difference, op=MPI.MAX)
    if rank == 0:
        print("%s: %d points on %d processes, max |distributed - serial| = %.3g"
              % (method, len(points), count, worst))
    vtkMultiProcessController.SetGlobalController(None)
    controller.Finalize(1)  # mpi4py finalises MPI at exit
    return worst


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    sys.exit(0 if main(*sys.argv[1:]) == 0.0 else 1)
