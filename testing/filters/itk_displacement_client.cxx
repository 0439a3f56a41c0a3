#include "itk_displacement_client.h"

#include "itkDisplacementFieldTransform.h"
#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkMetaImageIOFactory.h"
#include "itkNiftiImageIOFactory.h"
#include "itkNrrdImageIOFactory.h"
#include "itkVector.h"

namespace barylab_test
{
std::vector<std::array<double, 3>> ItkTransformPoints(
  const std::string& path, const std::vector<std::array<double, 3>>& points)
{
  // no UseITK: the image IO factories are registered here, once
  static const bool registered = [] {
    itk::NiftiImageIOFactory::RegisterOneFactory();
    itk::NrrdImageIOFactory::RegisterOneFactory();
    itk::MetaImageIOFactory::RegisterOneFactory();
    return true;
  }();
  (void)registered;
  using FieldImage = itk::Image<itk::Vector<double, 3>, 3>;
  using Transform = itk::DisplacementFieldTransform<double, 3>;
  auto reader = itk::ImageFileReader<FieldImage>::New();
  reader->SetFileName(path);
  reader->Update();
  auto transform = Transform::New();
  transform->SetDisplacementField(reader->GetOutput());
  std::vector<std::array<double, 3>> out;
  out.reserve(points.size());
  for (const auto& p : points)
  {
    Transform::InputPointType x;
    for (unsigned a = 0; a < 3; ++a)
      x[a] = p[a];
    const Transform::OutputPointType y = transform->TransformPoint(x);
    out.push_back({ y[0], y[1], y[2] });
  }
  return out;
}
} // namespace barylab_test
