#include "vtkBarySurfaceCorrespondence.h"

#include "vtkBaryFilterErrors.h"
#include "vtkBarySurfaceData.h"

#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include "core/surface/correspondence.h"

#include <algorithm>
#include <limits>

vtkStandardNewMacro(vtkBarySurfaceCorrespondence);

struct vtkBarySurfaceCorrespondence::Internals
{
  vtkBarySurfaceData::Cache Target, Source;
  std::vector<std::string> Arrays;
};

vtkBarySurfaceCorrespondence::vtkBarySurfaceCorrespondence()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(4);
  const bary::CorrespondenceOptions defaults;
  this->Gamma = defaults.inverse.gamma;
  this->RoundTripTolerance = defaults.round_trip_tolerance;
  this->SurfaceTolerance = bary::kDefaultSurfaceTolerance;
  this->SetEmbeddingArrayName(vtkBarySurfaceData::DefaultEmbeddingName());
}

vtkBarySurfaceCorrespondence::~vtkBarySurfaceCorrespondence()
{
  this->SetEmbeddingArrayName(nullptr);
}

void vtkBarySurfaceCorrespondence::AddArrayName(const char* name)
{
  if (name)
  {
    this->Internal->Arrays.emplace_back(name);
    this->Modified();
  }
}

void vtkBarySurfaceCorrespondence::ClearArrayNames()
{
  this->Internal->Arrays.clear();
  this->Modified();
}

int vtkBarySurfaceCorrespondence::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), port % 2 == 0 ? "vtkPolyData" : "vtkPointSet");
  return 1;
}

int vtkBarySurfaceCorrespondence::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* target = vtkPolyData::GetData(inputVector[0]);
  vtkPointSet* targetAnchors = vtkPointSet::GetData(inputVector[1]);
  vtkPolyData* source = vtkPolyData::GetData(inputVector[2]);
  vtkPointSet* sourceAnchors = vtkPointSet::GetData(inputVector[3]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfUndefined = this->NumberOfFlipped = 0;
  this->FlippedAreaFraction = this->Stretch = this->StretchBest95 = 0;
  try
  {
    const std::string name = this->EmbeddingArrayName ? this->EmbeddingArrayName : "";
    const auto wt = this->Internal->Target.Get(target, name);
    const auto ws = this->Internal->Source.Get(source, name);
    const auto ta = vtkBarySurfaceData::Locate(wt->mesh(), targetAnchors, this->SurfaceTolerance, "target anchor");
    const auto sa = vtkBarySurfaceData::Locate(ws->mesh(), sourceAnchors, this->SurfaceTolerance, "source anchor");
    std::vector<bary::SurfacePoint> vertices(static_cast<std::size_t>(wt->mesh().vertex_count()));
    for (bary::Index v = 0; v < wt->mesh().vertex_count(); ++v)
    {
      auto& p = vertices[static_cast<std::size_t>(v)];
      p.face = wt->mesh().vertex_faces[static_cast<std::size_t>(wt->mesh().face_offsets[static_cast<std::size_t>(v)])];
      for (int k = 0; k < 3; ++k)
        p.barycentric(k) = wt->mesh().F(p.face, k) == v ? 1.0 : 0.0;
    }
    bary::CorrespondenceOptions options;
    options.inverse.gamma = this->Gamma;
    options.inverse.threads = options.forward.threads = this->NumberOfThreads;
    options.round_trip_tolerance = this->RoundTripTolerance;
    const bary::SurfaceMap map = bary::map_surface_points(*wt, ta, vertices, *ws, sa, options,
      [this](double f) {
        this->UpdateProgress(f);
        return !this->GetAbortExecute();
      });
    const bary::MapDistortion d = bary::map_distortion(wt->mesh(), ws->mesh(), map);

    output->ShallowCopy(target);
    const vtkIdType n = target->GetNumberOfPoints();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // The source's arrays at the images.
    std::vector<std::string> names = this->Internal->Arrays;
    if (names.empty())
      for (int i = 0; i < source->GetPointData()->GetNumberOfArrays(); ++i)
      {
        vtkDataArray* a = source->GetPointData()->GetArray(i);
        if (a && a->GetName() && name != a->GetName())
          names.emplace_back(a->GetName());
      }
    for (const std::string& array_name : names)
    {
      vtkDataArray* in = source->GetPointData()->GetArray(array_name.c_str());
      if (!in)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "the source has no point array '" + array_name + "' to transfer");
      vtkNew<vtkDoubleArray> out;
      out->SetName(array_name.c_str());
      out->SetNumberOfComponents(in->GetNumberOfComponents());
      out->SetNumberOfTuples(n);
      for (vtkIdType v = 0; v < n; ++v)
      {
        const bary::SurfacePoint& p = map.image[static_cast<std::size_t>(v)];
        for (int c = 0; c < in->GetNumberOfComponents(); ++c)
        {
          double value = nan;
          if (p.face >= 0)
          {
            value = 0;
            for (int k = 0; k < 3; ++k)
              value += p.barycentric(k) * in->GetComponent(ws->mesh().F(p.face, k), c);
          }
          out->SetComponent(v, c, value);
        }
      }
      output->GetPointData()->AddArray(out);
    }
    vtkNew<vtkDoubleArray> position;
    position->SetName("SourcePosition");
    position->SetNumberOfComponents(3);
    position->SetNumberOfTuples(n);
    vtkNew<vtkDoubleArray> error;
    error->SetName("RoundTripError");
    error->SetNumberOfTuples(n);
    vtkNew<vtkUnsignedCharArray> defined;
    defined->SetName("Defined");
    defined->SetNumberOfTuples(n);
    for (vtkIdType v = 0; v < n; ++v)
    {
      const bary::SurfacePoint& p = map.image[static_cast<std::size_t>(v)];
      for (int c = 0; c < 3; ++c)
      {
        double x = nan;
        if (p.face >= 0)
        {
          x = 0;
          for (int k = 0; k < 3; ++k)
            x += p.barycentric(k) * ws->mesh().V(ws->mesh().F(p.face, k), c);
        }
        position->SetComponent(v, c, x);
      }
      error->SetValue(v, map.round_trip_error[static_cast<std::size_t>(v)]);
      defined->SetValue(v, map.defined[static_cast<std::size_t>(v)]);
    }
    output->GetPointData()->AddArray(position);
    output->GetPointData()->AddArray(error);
    output->GetPointData()->AddArray(defined);
    // SourceFaceId / SourceBarycentric: the image on the source.
    {
      vtkNew<vtkPolyData> tmp;
      tmp->SetPoints(target->GetPoints());
      vtkBarySurfaceData::AddSurfacePointArrays(tmp, map.image);
      for (const char* from : { "FaceId", "Barycentric" })
      {
        vtkDataArray* a = tmp->GetPointData()->GetArray(from);
        a->SetName((std::string("Source") + from).c_str());
        output->GetPointData()->AddArray(a);
      }
    }
    vtkNew<vtkDoubleArray> stretch;
    stretch->SetName("Stretch");
    stretch->SetNumberOfTuples(d.stretch.size());
    vtkNew<vtkUnsignedCharArray> flipped;
    flipped->SetName("Flipped");
    flipped->SetNumberOfTuples(d.stretch.size());
    for (vtkIdType f = 0; f < d.stretch.size(); ++f)
    {
      stretch->SetValue(f, d.stretch(f));
      flipped->SetValue(f, d.flipped[static_cast<std::size_t>(f)]);
    }
    output->GetCellData()->AddArray(stretch);
    output->GetCellData()->AddArray(flipped);
    this->NumberOfUndefined = map.undefined;
    this->NumberOfFlipped = d.flipped_count;
    this->FlippedAreaFraction = d.flipped_area_fraction;
    this->Stretch = d.stretch_all;
    this->StretchBest95 = d.stretch_best95;
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBarySurfaceCorrespondence::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "EmbeddingArrayName: " << (this->EmbeddingArrayName ? this->EmbeddingArrayName : "(none)")
     << "\n"
     << indent << "Gamma: " << this->Gamma << "\n"
     << indent << "RoundTripTolerance: " << this->RoundTripTolerance << "\n"
     << indent << "SurfaceTolerance: " << this->SurfaceTolerance << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
