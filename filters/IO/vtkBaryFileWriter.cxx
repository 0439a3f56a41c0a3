#include "vtkBaryFileWriter.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryConversion.h"

#include "core/common/error.h"

#include "vtkAlgorithm.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"

#include <exception>

vtkStandardNewMacro(vtkBaryFileWriter);

void vtkBaryFileWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

bool vtkBaryFileWriter::CanWriteFile(const char* path)
{
  return path && vtkBaryDataIO::CanWrite(path);
}

int vtkBaryFileWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  return 1;
}

void vtkBaryFileWriter::WriteData()
{
  // vtkWriter::WriteData returns nothing: an error sets the error code, which Write() reports
  // by returning 0 (vtkWriter::RequestData), as VTK's writers do.
  try
  {
    vtkBaryDataIO::Write(vtkDataSet::SafeDownCast(this->GetInput()), this->FileName);
  }
  catch (const bary::Error& e)
  {
    this->SetErrorCode(vtkBaryConversion::ToVTKErrorCode(e.code()));
    vtkErrorMacro(<< e.what());
  }
  catch (const std::exception& e)
  {
    this->SetErrorCode(vtkBaryConversion::ToVTKErrorCode(bary::ErrorCode::Internal));
    vtkErrorMacro(<< "Unexpected failure: " << e.what());
  }
}
