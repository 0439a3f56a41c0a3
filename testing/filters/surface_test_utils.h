#pragma once
/// @file surface_test_utils.h
/// Surfaces for the tests of the BaryLabSurface filters: a triangulated flat square and a
/// sphere from VTK's sources, an embedding array attached by hand.

#include "vtkDoubleArray.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkSphereSource.h"
#include "vtkTriangleFilter.h"

namespace barylab_test
{

/// The square [-1, 1]^2 at z = 0, n by n quads split into triangles.
inline vtkSmartPointer<vtkPolyData> FlatSquare(int n)
{
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(-1, -1, 0);
  plane->SetPoint1(1, -1, 0);
  plane->SetPoint2(-1, 1, 0);
  plane->SetResolution(n, n);
  plane->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(plane->GetOutputPort());
  triangles->Update();
  vtkSmartPointer<vtkPolyData> result = triangles->GetOutput();
  result->GetPointData()->Initialize(); // no normals or texture coordinates
  return result;
}

/// A unit sphere from vtkSphereSource (closed, triangles).
inline vtkSmartPointer<vtkPolyData> Sphere(int theta, int phi)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);
  sphere->SetThetaResolution(theta);
  sphere->SetPhiResolution(phi);
  sphere->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  sphere->Update();
  vtkSmartPointer<vtkPolyData> result = sphere->GetOutput();
  result->GetPointData()->Initialize();
  return result;
}

/// Attaches the points' own coordinates, padded with `padding` zero columns, as `Embedding`.
inline void EmbedAsIs(vtkPolyData* surface, int padding = 0)
{
  vtkNew<vtkDoubleArray> e;
  e->SetName("Embedding");
  e->SetNumberOfComponents(3 + padding);
  e->SetNumberOfTuples(surface->GetNumberOfPoints());
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
  {
    double x[3];
    surface->GetPoint(i, x);
    for (int k = 0; k < 3 + padding; ++k)
      e->SetComponent(i, k, k < 3 ? x[k] : 0.0);
  }
  surface->GetPointData()->AddArray(e);
}

} // namespace barylab_test
