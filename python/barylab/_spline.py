"""C1 spline deformations (Rodrigues et al. 2014) from Python: ``barylab spline create``,
``edit`` and ``deform`` over the wrapped filters of barylab.BaryLabSpline
(vtkBarySplineSource, vtkBarySplineEdit, vtkBarySplineDeform), numpy in and out.
"""

import json

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray

from ._pipeline import BaryLabError, _as_dataset, point_array, points_of, run, write
from .BaryLabSpline import vtkBarySplineDeform, vtkBarySplineEdit, vtkBarySplineSource


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
    return _run_to_output(source, output)


def spline_deform_data(spline, model, output=None):
    """The ``barylab spline deform`` job (vtkBarySplineDeform): ``model`` (a point set, a file,
    or an (n, 2|3) array) deformed by the spline grid ``spline`` (spline_create's output or a
    .vtu), with the point array ``SplineJacobian``. Every point must lie in the domain (and, for
    a prism, in its z range): BaryLabError naming the first that does not."""
    filter_ = vtkBarySplineDeform()
    filter_.SetInputData(0, _as_dataset(model, "model"))
    filter_.SetSplineData(_as_dataset(spline, "spline"))
    return _run_to_output(filter_, output)


def spline_deform(spline, model):
    """The deformed model's points as an (n_points, 3) array and the xy Jacobian determinant at
    each point, (n_points,) (see spline_deform_data)."""
    data = spline_deform_data(spline, model)
    return points_of(data), point_array(data, "SplineJacobian")[:, 0]


def _run_to_output(algorithm, output=None):
    """Runs ``algorithm`` (errors raised) and returns a copy of its output, written to
    ``output`` when a path is given."""
    run(algorithm)
    result = algorithm.GetOutputDataObject(0).NewInstance()
    result.ShallowCopy(algorithm.GetOutputDataObject(0))
    if output is not None:
        write(result, output)
    return result


_EDIT_KEYS = {"op", "near", "index", "by", "center", "angle_degrees", "factor", "delta_max",
              "spline"}
_TARGETS = {"xy": 0, "bottom": 1, "top": 2}


def _add_edit(filter_, k, e):
    """Edit ``k`` (a dict with the keys of ``barylab spline edit``'s EDITS.json) appended to
    vtkBarySplineEdit ``filter_``."""
    where = "edit %d" % k
    if not isinstance(e, dict):
        raise BaryLabError(where + " is not a dict")
    unknown = sorted(set(e) - _EDIT_KEYS)
    if unknown:
        raise BaryLabError("%s has an unknown key %r; keys: %s" % (where, unknown[0],
                                                                    ", ".join(sorted(_EDIT_KEYS))))
    target = _TARGETS.get(e.get("spline", "xy"))
    if target is None:
        raise BaryLabError("%s has spline %r; one of xy, bottom, top" % (where, e.get("spline")))
    index = e.get("index")
    anchors = None
    if index is not None:
        index = np.atleast_1d(np.asarray(index))
        if index.dtype.kind not in "iu":
            raise BaryLabError(where + "'s index must be integers")
        anchors = numpy_to_vtkIdTypeArray(index.astype(np.int64), deep=1)
    near = e.get("near")
    near_array = None
    if near is not None:
        near = np.atleast_2d(np.asarray(near, dtype=float))
        if near.shape[1] != 2:
            raise BaryLabError(where + "'s near must be positions (x, y)")
        near_array = numpy_to_vtk(np.ascontiguousarray(near), deep=1)
    if anchors is None and near_array is None:
        raise BaryLabError(where + ' names no anchor ("near" or "index")')
    delta_max = int(e.get("delta_max", 0))

    def number(key):
        if key not in e:
            raise BaryLabError('%s (%s) needs "%s"' % (where, e.get("op"), key))
        return e[key]

    op = e.get("op")
    if op == "translate":
        by = np.atleast_1d(np.asarray(number("by"), dtype=float))
        dx, dy = (by[0], by[1] if len(by) > 1 else 0.0)
        if target == 0 and len(by) != 2:
            raise BaryLabError(where + "'s by must be (dx, dy)")
        filter_.AddTranslateEdit(target, anchors, near_array, float(dx), float(dy), delta_max)
    elif op in ("rotate", "scale"):
        center = np.asarray(number("center"), dtype=float)
        if center.shape != (2,):
            raise BaryLabError(where + "'s center must be (x, y)")
        if op == "rotate":
            filter_.AddRotateEdit(target, anchors, near_array, center[0], center[1],
                                  float(number("angle_degrees")), delta_max)
        else:
            filter_.AddScaleEdit(target, anchors, near_array, center[0], center[1],
                                 float(number("factor")), delta_max)
    else:
        raise BaryLabError('%s has op %r; one of translate, rotate, scale' % (where, op))


def spline_edit_data(spline, edits, output=None):
    """The ``barylab spline edit`` job (vtkBarySplineEdit): the spline grid ``spline``
    (spline_create's output or a .vtu) after DECLeS ``edits``, applied in order: a list of dicts
    with the keys of the command line's EDITS.json (``op``: translate / rotate / scale,
    ``index`` and / or ``near``, ``by``, ``center``, ``angle_degrees``, ``factor``,
    ``delta_max``, ``spline``: xy / bottom / top), that file's ``{"edits": [...]}`` object, or
    its path. The output's field data holds the per-edit figures (``Residual``, ``Anchors``,
    ...); BaryLabError for an edit that cannot be applied, naming it."""
    if isinstance(edits, str):
        try:
            with open(edits) as f:
                edits = json.load(f)
        except (OSError, ValueError) as e:
            raise BaryLabError("cannot read the edits file %r: %s" % (edits, e)) from None
    if isinstance(edits, dict):
        if not isinstance(edits.get("edits"), list):
            raise BaryLabError('the edits have no "edits" list')
        edits = edits["edits"]
    filter_ = vtkBarySplineEdit()
    filter_.SetInputData(0, _as_dataset(spline, "spline"))
    for k, e in enumerate(edits):
        _add_edit(filter_, k, e)
    return _run_to_output(filter_, output)


def spline_edit(spline, edits):
    """The edited spline grid's control points as an (n, 3) array (see spline_edit_data)."""
    return points_of(spline_edit_data(spline, edits))

