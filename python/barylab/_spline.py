"""C1 spline deformations (Rodrigues et al. 2014) from Python: ``barylab spline create`` and
``barylab spline deform`` over the wrapped filters of barylab.BaryLabSpline
(vtkBarySplineSource, vtkBarySplineDeform), numpy in and out.

``barylab spline edit`` has no function here: vtkBarySplineEdit takes its edits as a C++
``std::vector`` (SetEdits), which VTK's Python wrapping cannot pass.
"""

import numpy as np

from ._pipeline import BaryLabError, _as_dataset, point_array, points_of, run, write
from .BaryLabSpline import vtkBarySplineDeform, vtkBarySplineSource


def spline_create(domain, degree=None, target_triangles=None, prism=None, fit_from=None,
                  fit_to=None, pin_border=False, output=None):
    """The ``barylab spline create`` job (vtkBarySplineSource): the identity spline deformation
    on ``domain`` (a triangulation in a plane, or one polygon, meshed with about
    ``target_triangles`` triangles; a vtkPolyData, a file, or for a polygon its (n, 2|3)
    vertices in order) as the spline grid, a vtkUnstructuredGrid of Bézier triangles of
    ``degree`` (see vtkBarySplineData; ``points_of`` gives its control points). ``prism``
    (bottom, top): a 2.5D deformation of that z range. ``fit_from``, ``fit_to`` (as many points
    each): instead the C1 spline fitted to the map fit_from -> fit_to by least squares.
    ``pin_border``: no edit moves the border's control points. ``output``: a .vtu to write."""
    from ._pipeline import polygon  # a bare (n, 2|3) array is one polygon, in order

    if isinstance(domain, np.ndarray) or isinstance(domain, (list, tuple)):
        domain = polygon(domain)
    source = vtkBarySplineSource()
    source.SetInputData(0, _as_dataset(domain, "domain"))
    if degree is not None:
        source.SetDegree(int(degree))
    if target_triangles is not None:
        source.SetTargetTriangles(int(target_triangles))
    if prism is not None:
        bottom, top = (float(v) for v in prism)
        source.SetPrism(True)
        source.SetPrismBottom(bottom)
        source.SetPrismTop(top)
    if (fit_from is None) != (fit_to is None):
        raise BaryLabError("fit_from and fit_to go together (the points where the map is "
                           "sampled and their images)")
    if fit_from is not None:
        source.SetFitFromData(_as_dataset(fit_from, "fit_from"))
        source.SetFitToData(_as_dataset(fit_to, "fit_to"))
    source.SetPinBorder(bool(pin_border))
    run(source)
    grid = source.GetOutput().NewInstance()
    grid.ShallowCopy(source.GetOutput())
    if output is not None:
        write(grid, output)
    return grid


def spline_deform_data(spline, model, output=None):
    """The ``barylab spline deform`` job (vtkBarySplineDeform): ``model`` (a point set, a file,
    or an (n, 2|3) array) deformed by the spline grid ``spline`` (spline_create's output or a
    .vtu), with the point array ``SplineJacobian``. Every point must lie in the domain (and, for
    a prism, in its z range): BaryLabError naming the first that does not."""
    filter_ = vtkBarySplineDeform()
    filter_.SetInputData(0, _as_dataset(model, "model"))
    filter_.SetSplineData(_as_dataset(spline, "spline"))
    run(filter_)
    result = filter_.GetOutputDataObject(0).NewInstance()
    result.ShallowCopy(filter_.GetOutputDataObject(0))
    if output is not None:
        write(result, output)
    return result


def spline_deform(spline, model):
    """The deformed model's points as an (n_points, 3) array and the xy Jacobian determinant at
    each point, (n_points,) (see spline_deform_data)."""
    data = spline_deform_data(spline, model)
    return points_of(data), point_array(data, "SplineJacobian")[:, 0]
