#include "vtkBaryFileReader.h"

#include "vtkBaryDataIO.h"
#include "vtkBaryFilterErrors.h"

#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"

vtkStandardNewMacro(vtkBaryFileReader);

vtkBaryFileReader::vtkBaryFileReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

vtkBaryFileReader::~vtkBaryFileReader() = default;

void vtkBaryFileReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

bool vtkBaryFileReader::CanReadFile(const char* path)
{
  return path && vtkBaryDataIO::CanRead(path);
}

int vtkBaryFileReader::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkDataSet");
  return 1;
}

int vtkBaryFileReader::RequestDataObject(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // The output's type is the file's, so the file is read here (once per update).
  this->Data = nullptr;
  try
  {
    this->Data = vtkBaryDataIO::Read(this->FileName);
  }
  VTKBARY_CATCH_ERRORS
  vtkInformation* info = outputVector->GetInformationObject(0);
  vtkDataObject* output = info->Get(vtkDataObject::DATA_OBJECT());
  if (!output || !output->IsA(this->Data->GetClassName()))
  {
    vtkSmartPointer<vtkDataObject> instance;
    instance.TakeReference(this->Data->NewInstance());
    info->Set(vtkDataObject::DATA_OBJECT(), instance);
  }
  return 1;
}

int vtkBaryFileReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkDataObject* output = vtkDataObject::GetData(outputVector, 0);
  if (!this->Data || !output)
  {
    vtkErrorMacro(<< "'" << this->FileName << "' was not read");
    return 0;
  }
  output->ShallowCopy(this->Data);
  this->Data = nullptr;
  return 1;
}
