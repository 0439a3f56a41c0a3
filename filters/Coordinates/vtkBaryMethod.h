/**
 * @class   vtkBaryMethod
 * @brief   Internal: the coordinate methods behind vtkBaryCoordinates and
 *          vtkBaryCageDeformation, dispatched from one place.
 *
 * Every method BaryLab offers is listed in Method and computed by Compute(); both public
 * filters (and the command line) go through here, so a new method is added once.
 */
#ifndef vtkBaryMethod_h
#define vtkBaryMethod_h

#include "BaryLabFiltersModule.h"
#include "vtkBaryConversion.h"
#include "vtkObject.h"

#include "core/progress.h"
#include "core/types.h"

#include <string>
#include <vector>

/// Parameters shared by every filter that computes weights.
struct vtkBaryMethodParameters
{
  int Method = 0;                  ///< vtkBaryCoordinates::Methods
  double BoundaryTolerance = 1e-10; ///< relative to the cage diameter
  bool ValidateCage = true;
  int NumberOfThreads = 0; ///< 0 = default

  bool operator==(const vtkBaryMethodParameters& o) const
  {
    return Method == o.Method && BoundaryTolerance == o.BoundaryTolerance &&
      ValidateCage == o.ValidateCage;
  }
};

/// What Compute() returns besides the weights.
struct vtkBaryMethodReport
{
  vtkIdType Inside = 0, Outside = 0, Boundary = 0;
  std::vector<vtkIdType> Undefined; ///< points whose weights are undefined (NaN rows)
  std::vector<unsigned char> Location; ///< per point: 0 inside, 1 outside, 2 on the cage
};

class BARYLABFILTERS_NO_EXPORT vtkBaryMethod : public vtkObject
{
public:
  static vtkBaryMethod* New();
  vtkTypeMacro(vtkBaryMethod, vtkObject);

  /// Weights (#P by #C, core control order) of @p points w.r.t. @p cage.
  /// @throws bary::Error
  static bary::DenseWeights Compute(const vtkBaryCage& cage, const Eigen::MatrixXd& points,
    const vtkBaryMethodParameters& parameters, const bary::ProgressCallback& progress,
    vtkBaryMethodReport* report);

protected:
  vtkBaryMethod() = default;
  ~vtkBaryMethod() override = default;

private:
  vtkBaryMethod(const vtkBaryMethod&) = delete;
  void operator=(const vtkBaryMethod&) = delete;
};

#endif
