#pragma once
/// @file itk_displacement_client.h
/// The real client of BaryLab's displacement fields: ITK 5.2 itself, behind a plain interface
/// so that ITK's headers (and the Eigen copy they bundle, which clashes with the system Eigen
/// that BaryLab's headers include) stay in itk_displacement_client.cxx.

#include <array>
#include <string>
#include <vector>

namespace barylab_test
{
/// Reads @p path with itk::ImageFileReader as itk::Image<itk::Vector<double, 3>, 3> and applies
/// it as itk::DisplacementFieldTransform<double, 3> to @p points. Throws std::exception (ITK's)
/// when the file cannot be read.
std::vector<std::array<double, 3>> ItkTransformPoints(
  const std::string& path, const std::vector<std::array<double, 3>>& points);
}
