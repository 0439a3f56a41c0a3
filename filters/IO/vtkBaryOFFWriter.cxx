#include "vtkBaryOFFWriter.h"

#include "vtkCellArray.h"
#include "vtkErrorCode.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <fstream>
#include <iomanip>

vtkStandardNewMacro(vtkBaryOFFWriter);

int vtkBaryOFFWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

void vtkBaryOFFWriter::WriteData()
{
  vtkPolyData* input = vtkPolyData::SafeDownCast(this->GetInput());
  if (!input)
  {
    vtkErrorMacro(<< "OFF files hold polygon meshes: the input must be vtkPolyData.");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return;
  }
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "No file name set.");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return;
  }
  std::ofstream out(this->FileName);
  if (!out)
  {
    vtkErrorMacro(<< "Cannot open '" << this->FileName << "' for writing.");
    this->SetErrorCode(vtkErrorCode::CannotOpenFileError);
    return;
  }
  if (input->GetNumberOfStrips() > 0)
    vtkWarningMacro(<< "Triangle strips are not written; triangulate first.");
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType np = input->GetNumberOfPoints();
  out << "OFF\n" << np << ' ' << polys->GetNumberOfCells() << " 0\n";
  out << std::setprecision(17);
  for (vtkIdType i = 0; i < np; ++i)
  {
    double x[3];
    input->GetPoint(i, x);
    out << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
  }
  const vtkIdType* ids;
  vtkIdType n;
  for (polys->InitTraversal(); polys->GetNextCell(n, ids);)
  {
    out << n;
    for (vtkIdType k = 0; k < n; ++k)
      out << ' ' << ids[k];
    out << '\n';
  }
  out.flush();
  if (!out)
  {
    vtkErrorMacro(<< "Writing '" << this->FileName << "' failed (disk full?).");
    this->SetErrorCode(vtkErrorCode::OutOfDiskSpaceError);
  }
}

void vtkBaryOFFWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}
