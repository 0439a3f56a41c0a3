"""BaryLab: generalized barycentric coordinates and deformation weights, from Python.

Two layers, on the same VTK filters as the ``barylab`` command line and viewer:

* every BaryLab filter, reader and writer, wrapped by VTK's own Python wrapping
  (``barylab.vtkBaryCoordinates``, ``barylab.vtkBaryCageDeformation``, ``barylab.vtkBaryFileReader``,
  ...; also from their modules ``barylab.BaryLabFilters``, ``barylab.BaryLabIO``,
  ``barylab.BaryLabSpline``, ``barylab.BaryLabSurface``): they connect to any VTK pipeline;
* functions with numpy arrays in and out, one per command-line job: ``weights``, ``deform``,
  ``animate``, ``skin``, ``statistics``, ``locality``, ``reduce``, ``fields``, ``mesh``,
  ``embed``, ``average``, ``inverse_average``, ``curve``, ``remesh``, ``transfer``,
  ``spline_create``, ``spline_edit``, ``spline_deform``, ``read``, ``write`` (see docs/python.md).
  Filter errors are raised as ``BaryLabError`` with the filter's message.
"""

from .BaryLabFilters import *  # noqa: F401,F403
from .BaryLabIO import *  # noqa: F401,F403

try:  # built in every tree that builds the Python package; tolerated if left out
    from .BaryLabSpline import *  # noqa: F401,F403
except ImportError:  # pragma: no cover
    pass
try:
    from .BaryLabSurface import *  # noqa: F401,F403
except ImportError:  # pragma: no cover
    pass

from ._pipeline import (  # noqa: F401
    BaryLabError,
    BaryLabWarning,
    animate,
    animate_data,
    compute_weights,
    configure,
    deform,
    deform_data,
    dense,
    fields,
    gradient_norms,
    level_sets,
    locality,
    mesh,
    method_names,
    point_array,
    points_of,
    polydata,
    polygon,
    read,
    reduce,
    run,
    skin,
    statistics,
    weights,
    write,
    write_time_series,
)

try:
    from ._spline import (spline_create, spline_deform, spline_deform_data,  # noqa: F401
                          spline_edit, spline_edit_data)
except ImportError:  # pragma: no cover
    pass
try:
    from ._surface import (  # noqa: F401
        average,
        average_data,
        curve,
        curve_data,
        embed,
        embed_data,
        inverse_average,
        inverse_average_data,
        morph_frames,
        remesh,
        remesh_data,
        transfer,
        transfer_data,
        with_embedding,
    )
except ImportError:  # pragma: no cover
    pass
