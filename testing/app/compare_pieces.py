#!/usr/bin/python3
"""Compares a distributed run's pieces (.pvtp / .pvtu) with the serial run's file, point by
point through the pieces' GlobalPointIds (the point's index in the serial model): the same
coordinates, and the point array ARRAY within TOLERANCE (0: bitwise). Every point of the serial
file must appear in some piece, and owned points (not flagged duplicate in vtkGhostType) exactly
once. Exit code 0 when they agree, 1 with the first difference otherwise.

usage: compare_pieces.py SERIAL PARALLEL ARRAY TOLERANCE"""
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import (vtkXMLPPolyDataReader, vtkXMLPUnstructuredGridReader,
                                 vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader)


def read(path):
    readers = {".vtp": vtkXMLPolyDataReader, ".vtu": vtkXMLUnstructuredGridReader,
               ".pvtp": vtkXMLPPolyDataReader, ".pvtu": vtkXMLPUnstructuredGridReader}
    reader = readers[path[path.rfind("."):]]()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def main(serial_path, parallel_path, array, tolerance):
    serial, parallel = read(serial_path), read(parallel_path)
    if serial.GetNumberOfPoints() == 0:
        return "the serial file has no points"
    ids = parallel.GetPointData().GetArray("GlobalPointIds")
    if ids is None:  # a whole data set (an animation's frame): the same points in order
        if parallel.GetNumberOfPoints() != serial.GetNumberOfPoints():
            return "no GlobalPointIds, and %d points for %d" % (
                parallel.GetNumberOfPoints(), serial.GetNumberOfPoints())
        ids = np.arange(serial.GetNumberOfPoints())
    else:
        ids = vtk_to_numpy(ids)
    ghosts = parallel.GetPointData().GetArray("vtkGhostType")
    owned = np.ones(len(ids), bool) if ghosts is None else (vtk_to_numpy(ghosts) & 1) == 0  # DUPLICATEPOINT
    counts = np.bincount(ids[owned], minlength=serial.GetNumberOfPoints())
    if len(counts) != serial.GetNumberOfPoints() or np.any(counts != 1):
        return "owned points are not each serial point once (counts %s)" % np.unique(counts)
    xs = vtk_to_numpy(serial.GetPoints().GetData())[ids]
    xp = vtk_to_numpy(parallel.GetPoints().GetData())
    if not np.array_equal(xs, xp):
        return "coordinates differ (max %g)" % np.abs(xs - xp).max()
    a = parallel.GetPointData().GetArray(array)
    b = serial.GetPointData().GetArray(array)
    if a is None or b is None:
        return "no point array '%s' in %s" % (array, "the pieces" if a is None else "the serial file")
    ws, wp = vtk_to_numpy(b), vtk_to_numpy(a)
    ws = ws[ids]
    if ws.shape != wp.shape:
        return "array shapes differ: serial %s, pieces %s" % (ws.shape, wp.shape)
    if not np.all(np.isfinite(ws) == np.isfinite(wp)):
        return "NaN rows differ"
    diff = np.abs(np.nan_to_num(ws) - np.nan_to_num(wp)).max()
    print("%s: %d points (and %d duplicates in the pieces), max |difference| %.3g (tolerance %g)"
          % (array, serial.GetNumberOfPoints(), int((~owned).sum()), diff, tolerance))
    if diff > tolerance or (tolerance == 0 and not np.array_equal(np.nan_to_num(ws), np.nan_to_num(wp))):
        return "max difference %.3g above the tolerance %g" % (diff, tolerance)
    return None


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    problem = main(sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]))
    if problem:
        print("compare_pieces: " + problem, file=sys.stderr)
        sys.exit(1)
