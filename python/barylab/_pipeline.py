"""BaryLab's Python layer: numpy in and out, one function per command-line job.

Everything numerical happens in BaryLab's VTK filters (the wrapped classes of
barylab.BaryLabFilters and barylab.BaryLabIO); this module only converts between numpy
arrays and VTK data, configures the filters and turns their error events into exceptions.
Methods, settings, their defaults and ranges are the filters' (BaryLab's one settings table):
settings are passed by their table keys (``lbc_max_iterations=5000``), as
vtkBaryWeightMethod.SetSetting takes them.
"""

import os
import warnings

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray, vtkIdTypeArray, vtkPoints
from vtkmodules.vtkCommonDataModel import (
    vtkCellArray,
    vtkCellTypes,
    vtkDataObject,
    vtkDataSet,
    vtkGenericCell,
    vtkPointSet,
    vtkPolyData,
)
from vtkmodules.vtkFiltersCore import vtkAppendPolyData, vtkContourFilter
from vtkmodules.vtkFiltersGeneral import vtkGradientFilter

from .BaryLabFilters import (
    vtkBaryCageDeformation,
    vtkBaryCageMesher,
    vtkBaryCoordinates,
    vtkBaryErrorObserver,
    vtkBaryLinearBlendSkinning,
    vtkBaryLocalityStatistics,
    vtkBaryReduceWeights,
    vtkBaryWeightMethod,
    vtkBaryWeightStatistics,
)
from .BaryLabIO import vtkBaryFileReader, vtkBaryFileWriter


class BaryLabError(RuntimeError):
    """A BaryLab filter refused its input or failed; the message is the filter's.

    ``code`` is the algorithm's error code (vtkBaryConversion::ToVTKErrorCode of the
    bary::ErrorCode), 0 when the error did not come from a filter's request.
    """

    def __init__(self, message, code=0):
        super().__init__(message)
        self.code = code


class BaryLabWarning(UserWarning):
    """A warning a BaryLab filter reported (e.g. an ignored domain, NaN rows)."""


# --- running filters --------------------------------------------------------------------------

def run(algorithm):
    """Updates ``algorithm``: its first error becomes a BaryLabError with the filter's message
    (VTK's "ERROR: In file, line" prefix removed), its warnings Python warnings (BaryLabWarning).
    Nothing is printed."""
    observer = vtkBaryErrorObserver()
    observer.Observe(algorithm)
    try:
        algorithm.Update()
    finally:
        observer.Release()
    for message in observer.GetWarnings():
        warnings.warn(message, BaryLabWarning, stacklevel=3)
    if observer.HasError():
        raise BaryLabError(observer.GetFirstError(), algorithm.GetErrorCode())
    return algorithm


class _ObjectErrors:
    """Collects the error events of a vtkObject that is not an algorithm (the weight method)."""

    def __init__(self, obj):
        self.messages = []
        self.obj = obj
        self.tag = obj.AddObserver(vtkCommand.ErrorEvent, self._on_error)

    @calldata_type(VTK_STRING)
    def _on_error(self, caller, event, message):
        self.messages.append(vtkBaryErrorObserver.CleanMessage(message))

    def close(self):
        self.obj.RemoveObserver(self.tag)
        if self.messages:
            raise BaryLabError(self.messages[0])


# --- numpy <-> VTK ----------------------------------------------------------------------------

def _points_array(points, name="points"):
    """An (n, 3) float64 array from (n, 2) or (n, 3) array-likes (z = 0 for 2D)."""
    a = np.asarray(points, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] not in (2, 3):
        raise ValueError(f"{name} must be an (n, 2) or (n, 3) array, not of shape {a.shape}")
    if a.shape[1] == 2:
        a = np.hstack([a, np.zeros((a.shape[0], 1))])
    return np.ascontiguousarray(a)


def _vtk_points(points, name="points"):
    p = vtkPoints()
    p.SetDataTypeToDouble()
    p.SetData(numpy_support.numpy_to_vtk(_points_array(points, name), deep=True))
    return p


def _cell_array(cells):
    """A vtkCellArray from a list of index sequences or an (m, k) integer array."""
    if isinstance(cells, np.ndarray) and cells.ndim == 2:
        lists = [row for row in cells]
    else:
        lists = [np.asarray(c).ravel() for c in cells]
    offsets = np.zeros(len(lists) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([len(c) for c in lists])
    connectivity = (np.concatenate(lists).astype(np.int64) if lists
                    else np.zeros(0, dtype=np.int64))
    array = vtkCellArray()
    array.SetData(numpy_support.numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_support.numpy_to_vtkIdTypeArray(connectivity, deep=True))
    return array


def polydata(points, polys=None, lines=None):
    """A vtkPolyData of ``points`` ((n, 2) or (n, 3)) with polygon cells ``polys`` and line
    cells ``lines`` (lists of point-index sequences, or (m, k) integer arrays). Bare points
    (no cells) are what the free-point methods (tcc, scc) and 2D cages given as points in order
    (an .obj with only ``v`` lines) are."""
    data = vtkPolyData()
    data.SetPoints(_vtk_points(points))
    if polys is not None:
        data.SetPolys(_cell_array(polys))
    if lines is not None:
        data.SetLines(_cell_array(lines))
    return data


def polygon(points):
    """A 2D cage: one polygon through ``points`` ((n, 2) or (n, 3) in a plane z = const) in
    order."""
    n = len(np.asarray(points))
    return polydata(points, polys=[np.arange(n)])


def points_of(data):
    """The points of a VTK point set as an (n, 3) numpy array (a copy)."""
    data = _as_dataset(data)
    if data.GetNumberOfPoints() == 0:
        return np.zeros((0, 3))
    return np.array([data.GetPoint(i) for i in range(data.GetNumberOfPoints())]) \
        if not isinstance(data, vtkPointSet) \
        else numpy_support.vtk_to_numpy(data.GetPoints().GetData()).astype(np.float64)


def point_array(data, name):
    """The point-data array ``name`` of ``data`` as a numpy array of shape (n_points, n_components)
    (a copy); KeyError if there is none."""
    array = _as_dataset(data).GetPointData().GetArray(name)
    if array is None:
        raise KeyError(f"the data set has no point-data array '{name}'")
    values = numpy_support.vtk_to_numpy(array).astype(np.float64)
    return values.reshape(array.GetNumberOfTuples(), array.GetNumberOfComponents())


def _as_dataset(data, name="data"):
    """A file path, a vtkDataSet, or an (n, 2|3) array of points (bare points)."""
    if isinstance(data, (str, os.PathLike)):
        return read(data)
    if isinstance(data, vtkDataSet):
        return data
    if data is None:
        raise ValueError(f"{name} is missing")
    return polydata(data)


def _as_polydata(data, name):
    data = _as_dataset(data, name)
    if not isinstance(data, vtkPolyData):
        raise TypeError(f"{name} must be a vtkPolyData (a cage or control points), "
                        f"not a {data.GetClassName()}")
    return data


def _with_weights(data, weights, array_name):
    """A shallow copy of ``data`` carrying ``weights`` ((n_points, n_controls)) as the point-data
    array ``array_name``."""
    data = _as_dataset(data)
    w = np.asarray(weights, dtype=np.float64)
    if w.ndim == 1:
        w = w.reshape(-1, 1)
    if w.ndim != 2 or w.shape[0] != data.GetNumberOfPoints():
        raise ValueError(f"weights must be an array of shape ({data.GetNumberOfPoints()}, "
                         f"n_controls) (one row per point), not {w.shape}")
    copy = data.NewInstance()
    copy.ShallowCopy(data)
    array = numpy_support.numpy_to_vtk(np.ascontiguousarray(w), deep=True,
                                       array_type=vtkDoubleArray().GetDataType())
    array.SetName(array_name)
    copy.GetPointData().AddArray(array)
    return copy


# --- files ------------------------------------------------------------------------------------

def read(path):
    """Reads any format BaryLab reads (.vtp .vtu .vtk .obj .stl .ply .off .mesh .tgf), validated
    (vtkBaryFileReader). Raises BaryLabError naming the file and the problem."""
    reader = vtkBaryFileReader()
    reader.SetFileName(os.fspath(path))
    run(reader)
    return reader.GetOutputDataObject(0)


def write(data, path):
    """Writes ``data`` by extension, atomically (vtkBaryFileWriter); .vtp/.vtu/.vtk keep the
    point data (weights). Raises BaryLabError naming the file and the problem."""
    writer = vtkBaryFileWriter()
    writer.SetInputData(_as_dataset(data))
    writer.SetFileName(os.fspath(path))
    run(writer)
    return os.fspath(path)


# --- weights ----------------------------------------------------------------------------------

def method_names():
    """The command-line names of the methods, in id order (from vtkBaryWeightMethod)."""
    return [vtkBaryWeightMethod.GetMethodName(i)
            for i in range(vtkBaryWeightMethod.NUMBER_OF_METHODS)]


def configure(weight_method, method="mvc", **settings):
    """Sets ``method`` (a name from method_names() or a vtkBaryWeightMethod.Methods value) and
    each setting by its table key on ``weight_method`` (a vtkBaryWeightMethod; ``user_weights``,
    tcc's s_i, as a sequence: one per control point). An unknown
    method or key, a non-finite value, or a value outside the setting's range (which the filter
    would clamp) raises BaryLabError; nothing is clamped silently."""
    if isinstance(method, str):
        if not weight_method.SetMethodByName(method):
            raise BaryLabError(f"unknown method '{method}' (one of: "
                               f"{', '.join(method_names())})")
    else:
        if not 0 <= int(method) < vtkBaryWeightMethod.NUMBER_OF_METHODS:
            raise BaryLabError(f"unknown method id {method}")
        weight_method.SetMethod(int(method))
    for key, value in settings.items():
        if np.ndim(value) > 0:
            # the table's one list setting (user_weights, tcc's s_i): the method's UserWeights
            # array, which the filter checks (one entry per control point, each >= 0)
            if key != "user_weights":
                raise BaryLabError(f"setting '{key}' takes one number, not a list")
            array = numpy_support.numpy_to_vtk(np.asarray(value, dtype=np.float64).ravel(),
                                               deep=True)
            array.SetName("UserWeights")
            weight_method.SetUserWeights(array)
            continue
        errors = _ObjectErrors(weight_method)
        weight_method.SetSetting(key, float(value))
        errors.close()
        got = weight_method.GetSetting(key)
        if got != float(value):
            raise BaryLabError(f"setting '{key}': {value} is outside its range "
                               f"(the nearest allowed value is {got:g})")
    return weight_method


def compute_weights(points, cage, method="mvc", domain=None, array_name="Weights", **settings):
    """The ``barylab weights`` job as a VTK data set: ``points`` (a data set, a file, or an
    (n, 2|3) array) with the point-data array ``array_name`` (one component per control) and
    "CageLocation" (and "FaceWeights" for Green coordinates), from vtkBaryCoordinates.
    ``cage``: a vtkPolyData (polydata(), polygon()), a file, or for the free-point methods an
    array of control points. ``domain``: a mesh of the cage's interior (harmonic, BBW, LBC) or
    BBW's domain for a skeleton."""
    filter_ = vtkBaryCoordinates()
    configure(filter_.GetWeightMethod(), method, **settings)
    filter_.SetWeightsArrayName(array_name)
    filter_.SetInputData(0, _as_dataset(points, "points"))
    filter_.SetCageData(_as_polydata(cage, "cage"))
    if domain is not None:
        filter_.SetDomainData(_as_dataset(domain, "domain"))
    run(filter_)
    output = filter_.GetOutputDataObject(0)
    result = output.NewInstance()
    result.ShallowCopy(output)
    return result


def weights(points, cage, method="mvc", domain=None, **settings):
    """Weights of ``points`` w.r.t. ``cage`` as an (n_points, n_controls) numpy array: row p holds
    the weights of point p, column i belongs to control point i (see compute_weights for the
    arguments; settings by table key, e.g. ``target_cells=2000``)."""
    data = compute_weights(points, cage, method, domain, array_name="Weights", **settings)
    return point_array(data, "Weights")


def mesh(cage, points=None, cage_dimension=0, target_cells=None, max_cell_size=None):
    """A triangulation (2D) or tetrahedralization (3D) of the cage's interior, with ``points``
    inserted as vertices (vtkBaryCageMesher's defaults unless given): the domain the mesh-based
    methods solve on."""
    mesher = vtkBaryCageMesher()
    mesher.SetCageData(_as_polydata(cage, "cage"))
    mesher.SetCageDimension(cage_dimension)
    if target_cells is not None:
        mesher.SetTargetNumberOfCells(int(target_cells))
    if max_cell_size is not None:
        mesher.SetMaximumCellSize(float(max_cell_size))
    if points is not None:
        mesher.SetPointsData(_as_dataset(points, "points"))
    run(mesher)
    return mesher.GetOutput()


# --- deformation ------------------------------------------------------------------------------

def deform_data(model, rest_cage, posed_cage, method="mvc", weights=None, array_name="Weights",
                **settings):
    """The ``barylab deform`` job as a VTK data set (vtkBaryCageDeformation): ``model`` moved with
    the cage from ``rest_cage`` to ``posed_cage`` (the moved control points: a point set, a file,
    or an (n_controls, 2|3) array, same order). ``weights`` (n_points, n_controls), when given,
    are used as they are; otherwise the model's array ``array_name`` if it has one, else the
    method's weights are computed."""
    model = _as_dataset(model, "model")
    rest = _as_polydata(rest_cage, "rest_cage")
    posed = _as_dataset(posed_cage, "posed_cage")
    chosen = configure(vtkBaryWeightMethod(), method, **settings)  # bad settings raise first
    if weights is not None:
        model = _with_weights(model, weights, array_name)
    elif (vtkBaryWeightMethod.IsPointBased(chosen.GetMethod())
          and model.GetPointData().GetArray(array_name) is None):
        # Free control points (tcc, scc) may get hull points added to the controls (the field
        # data "AddedControlPoints", vtkBaryCoordinates): as `barylab deform` does
        # (barylab::Deform), weights first; _deform keeps the added points where they are.
        model = compute_weights(model, rest, method, array_name=array_name, **settings)
    return _deform(model, rest, posed, method, array_name, settings)


def _deform(model, rest, posed, method, array_name, settings):
    """vtkBaryCageDeformation of ``model`` (a data set, with or without the weights array)
    from ``rest`` to ``posed``; the added control points of the model's field data
    "AddedControlPoints" (celestial hull points) are appended to both, unmoved, when the weights
    have their columns (as barylab::Deform)."""
    added = model.GetFieldData().GetArray("AddedControlPoints")
    given = model.GetPointData().GetArray(array_name)
    if (added is not None and given is not None and added.GetNumberOfTuples() > 0
            and given.GetNumberOfComponents()
            == rest.GetNumberOfPoints() + added.GetNumberOfTuples()):
        fixed = numpy_support.vtk_to_numpy(added).reshape(-1, 3)
        rest = polydata(np.vstack([points_of(rest), fixed]))
        posed = polydata(np.vstack([points_of(posed), fixed]))
    filter_ = vtkBaryCageDeformation()
    configure(filter_.GetWeightMethod(), method, **settings)
    filter_.SetWeightsArrayName(array_name)
    filter_.SetInputData(0, model)
    filter_.SetRestCageData(rest)
    filter_.SetDeformedCageData(posed)
    run(filter_)
    result = filter_.GetOutput().NewInstance()
    result.ShallowCopy(filter_.GetOutput())
    return result


def deform(model, rest_cage, posed_cage, method="mvc", weights=None, **settings):
    """The deformed model's points as an (n_points, 3) numpy array (see deform_data)."""
    return points_of(deform_data(model, rest_cage, posed_cage, method, weights, **settings))


def skin(model, weights, transforms, array_name="Weights"):
    """Linear blend skinning (vtkBaryLinearBlendSkinning): the points of ``model`` moved by
    x' = sum_j w_j(x) [A_j | t_j] (x, 1), ``transforms`` an (n_handles, 3, 4) array (one 3 x 4
    affine transform per weights column). Returns an (n_points, 3) array."""
    t = np.asarray(transforms, dtype=np.float64)
    if t.ndim != 3 or t.shape[1:] != (3, 4):
        raise ValueError(f"transforms must be an (n_handles, 3, 4) array, not of shape {t.shape}")
    array = numpy_support.numpy_to_vtk(np.ascontiguousarray(t.reshape(-1, 12)), deep=True)
    array.SetName("Transforms")
    filter_ = vtkBaryLinearBlendSkinning()
    filter_.SetInputData(_with_weights(model, weights, array_name))
    filter_.SetTransforms(array)
    filter_.SetWeightsArrayName(array_name)
    run(filter_)
    return points_of(filter_.GetOutput())


# --- statistics -------------------------------------------------------------------------------

def _table_columns(table):
    columns = {}
    for c in range(table.GetNumberOfColumns()):
        array = table.GetColumn(c)
        columns[table.GetColumnName(c)] = numpy_support.vtk_to_numpy(array).copy()
    return columns


def statistics(data, weights=None, cage=None, threshold=-1.0, cage_dimension=0,
               array_name="Weights"):
    """The ``barylab stats`` figures (vtkBaryWeightStatistics) of the weights on ``data`` (a data
    set carrying ``array_name``, or points with ``weights`` (n_points, n_controls)): a dict of the
    filter's one-row table ("points", "controls", "min_weight", "max_partition_error", ...,
    "max_reproduction_error" when ``cage`` is given) and "histogram": the number of points with
    exactly k significant weights, k = 0, 1, .... A negative threshold means 1e-3 / n_controls."""
    data = _as_dataset(data) if weights is None else _with_weights(data, weights, array_name)
    filter_ = vtkBaryWeightStatistics()
    filter_.SetInputData(0, data)
    if cage is not None:
        filter_.SetCageData(_as_polydata(cage, "cage"))
    filter_.SetWeightsArrayName(array_name)
    filter_.SetThreshold(float(threshold))
    filter_.SetCageDimension(int(cage_dimension))
    run(filter_)
    figures = {name: float(values[0])
               for name, values in _table_columns(filter_.GetOutput(0)).items()}
    figures["histogram"] = _table_columns(filter_.GetOutput(1))["points"].astype(np.int64)
    return figures


def reduce(data, weights=None, cage=None, threshold=-1.0, renormalization="rowsum",
           array_name="Weights"):
    """The ``barylab reduce`` job (vtkBaryReduceWeights): sparse weights, those above
    ``threshold`` (negative: 1e-3 / n_controls), rows renormalised by ``renormalization``
    ("rowsum", "affine": needs ``cage``, or "none"). Returns a dict with "indices"
    (n_points, K) int array of the kept controls, padded with -1, "values" (n_points, K),
    padded with 0, and the filter's figures "K", "threshold", "partition_error",
    "reproduction_error" (NaN without a cage), "max_dropped", "nonzeros", "memory_fraction",
    "csr_memory_fraction". ``deform(..., weights=dense(result, n_controls))`` deforms with them."""
    data = _as_dataset(data) if weights is None else _with_weights(data, weights, array_name)
    filter_ = vtkBaryReduceWeights()
    filter_.SetInputData(data)
    if cage is not None:
        filter_.SetCageData(_as_polydata(cage, "cage"))
    filter_.SetWeightsArrayName(array_name)
    filter_.SetThreshold(float(threshold))
    choices = {"none": filter_.SetRenormalizationToNone,
               "rowsum": filter_.SetRenormalizationToRowSum,
               "affine": filter_.SetRenormalizationToAffine}
    if renormalization not in choices:
        raise ValueError(f"unknown renormalization '{renormalization}' "
                         f"(one of: {', '.join(choices)})")
    choices[renormalization]()
    run(filter_)
    output = filter_.GetOutputDataObject(0)
    return {
        "indices": point_array(output, array_name + "Indices").astype(np.int64),
        "values": point_array(output, array_name + "Values"),
        "K": filter_.GetMaximumSupport(),
        "threshold": filter_.GetThresholdUsed(),
        "partition_error": filter_.GetPartitionError(),
        "reproduction_error": filter_.GetReproductionError(),
        "max_dropped": filter_.GetMaxDropped(),
        "nonzeros": filter_.GetNumberOfNonzeros(),
        "memory_fraction": filter_.GetMemoryFraction(),
        "csr_memory_fraction": filter_.GetCSRMemoryFraction(),
    }


def dense(sparse, n_controls):
    """The (n_points, n_controls) array of sparse weights from reduce() (a scatter, no algorithm)."""
    indices, values = sparse["indices"], sparse["values"]
    W = np.zeros((indices.shape[0], n_controls))
    rows, cols = np.nonzero(indices >= 0)
    W[rows, indices[rows, cols]] = values[rows, cols]
    return W


def locality(data, weights=None, threshold=-1.0, use_mesh_measure=True, array_name="Weights"):
    """Locality statistics of Zhang et al. 2014, §5 (vtkBaryLocalityStatistics): a dict with
    "t", "P" (P(t), Eq. 19-20), "k", "Q" (Q(k), Eq. 21), "influence_fraction" (per control) as
    numpy arrays, and "mean_support", "max_support", "threshold", "measure" ("uniform", "area"
    or "volume"). ``data``: a data set carrying ``array_name`` (a mesh: points weigh by their
    lumped area / volume), or points with ``weights`` (n_points, n_controls)."""
    data = _as_dataset(data) if weights is None else _with_weights(data, weights, array_name)
    filter_ = vtkBaryLocalityStatistics()
    filter_.SetInputData(data)
    filter_.SetWeightsArrayName(array_name)
    filter_.SetThreshold(float(threshold))
    filter_.SetUseMeshMeasure(bool(use_mesh_measure))
    run(filter_)
    result = {}
    result.update(_table_columns(filter_.GetPTable()))
    result.update(_table_columns(filter_.GetQTable()))
    result["influence_fraction"] = _table_columns(filter_.GetInfluenceTable())["influence_fraction"]
    result["mean_support"] = filter_.GetMeanSupport()
    result["max_support"] = filter_.GetMaxSupport()
    result["threshold"] = filter_.GetThresholdUsed()
    result["measure"] = filter_.GetMeasureUsedAsString()
    return result


# --- time series and animation ----------------------------------------------------------------

def write_time_series(frames, output_dir, prefix, period=1.0):
    """Writes data sets as ``output_dir/prefix_000.vtp``, ``_001``, ... (vtkBaryFileWriter) and
    the ParaView collection ``output_dir/prefix.pvd`` (time step of frame f: period * f / #frames;
    written last, atomically), the layout of ``barylab animate`` and ``transfer --morph``.
    Returns the .pvd's path."""
    frames = list(frames)
    if not frames:
        raise BaryLabError("no frames to write")
    prefix = str(prefix)
    if not prefix or "/" in prefix or "\\" in prefix or prefix in (".", ".."):
        raise BaryLabError("the prefix must be a file name without '/' (the frames are written "
                           "inside the output folder)")
    output_dir = os.fspath(output_dir)
    try:
        os.makedirs(output_dir, exist_ok=True)
    except OSError as error:
        raise BaryLabError(f"cannot create the folder '{output_dir}': {error.strerror}") from None
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for f, frame in enumerate(frames):
        name = f"{prefix}_{f:03d}.vtp"
        write(frame, os.path.join(output_dir, name))
        lines.append(f'    <DataSet timestep="{float(period) * f / len(frames):g}" group="" '
                     f'part="0" file="{name}"/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    path = os.path.join(output_dir, prefix + ".pvd")
    try:
        with open(path + ".tmp", "w") as out:
            out.write("\n".join(lines))
        os.replace(path + ".tmp", path)
    except OSError:
        raise BaryLabError(f"cannot write '{path}'") from None
    return path


def animate_data(model, rest_cage, frames, method="mvc", array_name="Weights", **settings):
    """The ``barylab animate`` job as a list of VTK data sets, one per frame: the weights of
    ``model`` w.r.t. ``rest_cage`` computed once (vtkBaryCoordinates), then the model deformed
    by each moved cage of ``frames`` (a sequence of point sets, files or (n_controls, 2|3)
    arrays, the rest cage's points moved, same order) with vtkBaryCageDeformation, as
    ``barylab animate`` does. Skeletons (bbw) are refused, as by the command line."""
    frames = list(frames)
    if not frames:
        raise BaryLabError("no frames to animate")
    chosen = configure(vtkBaryWeightMethod(), method, **settings)
    if chosen.GetMethod() == vtkBaryWeightMethod.BBW:
        raise BaryLabError("animate moves cages or control points; for skeletons use "
                           "deform(..., method='bbw') per pose")
    rest = _as_polydata(rest_cage, "rest_cage")
    posed = []
    for f, frame in enumerate(frames):
        data = _as_dataset(frame, f"frame {f}")
        if (not isinstance(data, vtkPointSet)
                or data.GetNumberOfPoints() != rest.GetNumberOfPoints()):
            raise BaryLabError(f"frame {f} must hold the {rest.GetNumberOfPoints()} points of the "
                               f"rest cage, moved (same order)")
        posed.append(data)
    weighted = compute_weights(model, rest, method, array_name=array_name, **settings)
    return [_deform(weighted, rest, p, method, array_name, settings) for p in posed]


def animate(model, rest_cage, frames, method="mvc", output_dir=None, prefix="animation",
            period=1.0, array_name="Weights", **settings):
    """The deformed model's points of every frame as an (n_frames, n_points, 3) array (see
    animate_data). With ``output_dir``, the frames are also written as ``barylab animate
    --output-dir --prefix --period`` writes them: ``prefix_000.vtp``, ... and ``prefix.pvd``."""
    if output_dir is not None and period is not None and not (np.isfinite(period) and period > 0):
        raise BaryLabError(f"period must be a finite number > 0, not {period}")
    deformed = animate_data(model, rest_cage, frames, method, array_name, **settings)
    if output_dir is not None:
        write_time_series(deformed, output_dir, prefix, period)
    return np.stack([points_of(d) for d in deformed])


# --- weight fields ----------------------------------------------------------------------------

def _max_cell_dimension(data):
    types = vtkCellTypes()
    data.GetCellTypes(types)
    dimension = 0
    for i in range(types.GetNumberOfTypes()):
        cell = vtkGenericCell()
        cell.SetCellType(types.GetCellType(i))
        dimension = max(dimension, cell.GetCellDimension())
    return dimension


def gradient_norms(data, weights=None, array_name="Weights"):
    """|grad w_i| at every point of a mesh carrying weights (``data`` with ``array_name``, or a
    mesh with ``weights`` (n_points, n_controls)): an (n_points, n_controls) array, from VTK's
    vtkGradientFilter, as ``barylab fields --output`` (its ``<array>GradientNorm``). A point
    cloud has no gradient: BaryLabError."""
    data = _as_dataset(data) if weights is None else _with_weights(data, weights, array_name)
    if data.GetPointData().GetArray(array_name) is None:
        raise BaryLabError(f"the data set has no point-data array '{array_name}'")
    if _max_cell_dimension(data) < 2:
        raise BaryLabError(f"gradient norms need a mesh (triangles, polygons or 3D cells); the "
                           f"data set has {data.GetNumberOfCells()} cells of dimension < 2")
    gradient = vtkGradientFilter()
    gradient.SetInputData(data)
    gradient.SetInputScalars(vtkDataObject.FIELD_ASSOCIATION_POINTS, array_name)
    gradient.SetResultArrayName("barylab_weight_gradient")
    run(gradient)
    G = point_array(gradient.GetOutputDataObject(0), "barylab_weight_gradient")
    return np.sqrt((G.reshape(G.shape[0], -1, 3) ** 2).sum(axis=2))


def level_sets(data, control=0, levels=None, weights=None, array_name="Weights"):
    """Level sets {w_control = level} of one weight as a vtkPolyData (lines in 2D, surfaces in
    3D) with the cell array ``level``, from VTK's vtkContourFilter, one per level, appended
    (vtkAppendPolyData), as ``barylab fields --level-sets``. ``levels`` default: 1e-3 /
    n_controls."""
    data = _as_dataset(data) if weights is None else _with_weights(data, weights, array_name)
    W = point_array(data, array_name)
    if not 0 <= int(control) < W.shape[1]:
        raise BaryLabError(f"control {control} does not exist (the weights have {W.shape[1]} "
                           f"components)")
    levels = [1e-3 / W.shape[1]] if levels is None else list(np.atleast_1d(levels))
    single = data.NewInstance()
    single.CopyStructure(data)
    values = numpy_support.numpy_to_vtk(np.ascontiguousarray(W[:, int(control)]), deep=True)
    values.SetName("weight")
    single.GetPointData().SetScalars(values)
    append = vtkAppendPolyData()
    for level in levels:
        if not np.isfinite(level):
            raise BaryLabError("a level value is not finite")
        contour = vtkContourFilter()
        contour.SetInputData(single)
        contour.SetValue(0, float(level))
        contour.SetComputeScalars(True)
        run(contour)
        piece = vtkPolyData()
        piece.ShallowCopy(contour.GetOutput())
        tag = numpy_support.numpy_to_vtk(np.full(piece.GetNumberOfCells(), float(level)), deep=True)
        tag.SetName("level")
        piece.GetCellData().AddArray(tag)
        append.AddInputData(piece)
    run(append)
    result = vtkPolyData()
    result.ShallowCopy(append.GetOutput())
    return result


def fields(data, weights=None, control=0, levels=None, array_name="Weights", output=None,
           level_sets_output=None):
    """The ``barylab fields`` job: a dict with "gradient_norm" (gradient_norms), its per-control
    "max" and "mean", and "level_sets" (level_sets of ``control`` at ``levels``). ``output``
    writes a copy of the data with ``<array>GradientNorm``, ``level_sets_output`` the level
    sets, as ``--output`` and ``--level-sets``."""
    data = _as_dataset(data) if weights is None else _with_weights(data, weights, array_name)
    norms = gradient_norms(data, array_name=array_name)
    result = {"gradient_norm": norms, "max": norms.max(axis=0) if len(norms) else norms[:0],
              "mean": norms.mean(axis=0) if len(norms) else norms[:0],
              "level_sets": level_sets(data, control, levels, array_name=array_name)}
    if output is not None:
        write(_with_weights(data, norms, array_name + "GradientNorm"), output)
    if level_sets_output is not None:
        write(result["level_sets"], level_sets_output)
    return result
