// vtkBarySurfaceCorrespondence: point data transferred through corresponding anchors; a surface
// mapped onto itself keeps its data where the map is defined, with stretch 1.
#include "vtkBarySurfaceCorrespondence.h"

#include "filters_test_utils.h"
#include "surface_test_utils.h"

#include "vtkCellData.h"
#include "vtkUnsignedCharArray.h"

using namespace barylab_test;

TEST(vtkBarySurfaceCorrespondence, ASurfaceOntoItselfKeepsItsData)
{
  auto sphere = Sphere(32, 24);
  EmbedAsIs(sphere, 5);
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  height->SetNumberOfTuples(sphere->GetNumberOfPoints());
  for (vtkIdType i = 0; i < sphere->GetNumberOfPoints(); ++i)
    height->SetValue(i, sphere->GetPoint(i)[2]);
  sphere->GetPointData()->AddArray(height);
  const double pi = std::acos(-1.0);
  std::vector<std::array<double, 3>> ring;
  for (int i = 0; i < 6; ++i)
  {
    const double a = 2 * pi * i / 6;
    ring.push_back({ 0.6 * std::cos(a), 0.6 * std::sin(a), 0.8 });
  }
  auto anchors = MakePointCloud(ring);
  vtkNew<vtkBarySurfaceCorrespondence> map;
  vtkNew<ErrorObserver> observer;
  observer->Attach(map);
  map->SetInputData(0, sphere);
  map->SetTargetAnchorsData(anchors);
  map->SetSourceData(sphere);
  map->SetSourceAnchorsData(anchors);
  ASSERT_EQ(RunPipeline(map), 1) << observer->AllErrors();
  vtkPolyData* out = map->GetOutput();
  vtkDataArray* h = out->GetPointData()->GetArray("Height");
  auto* defined = vtkUnsignedCharArray::SafeDownCast(out->GetPointData()->GetArray("Defined"));
  ASSERT_TRUE(h && defined);
  EXPECT_EQ(out->GetPointData()->GetArray("Embedding")->GetNumberOfComponents(), 8); // kept as is
  vtkIdType count = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    if (!defined->GetValue(i))
    {
      EXPECT_TRUE(std::isnan(h->GetComponent(i, 0)));
      continue;
    }
    ++count;
    EXPECT_NEAR(h->GetComponent(i, 0), sphere->GetPoint(i)[2], 1e-9);
  }
  EXPECT_GT(count, 50);
  EXPECT_EQ(map->GetNumberOfUndefined(), out->GetNumberOfPoints() - count);
  EXPECT_NEAR(map->GetStretch(), 1.0, 1e-9);
  EXPECT_EQ(map->GetNumberOfFlipped(), 0);
  EXPECT_NE(out->GetCellData()->GetArray("Stretch"), nullptr);

  // A missing array is named; so is a different number of anchors.
  map->AddArrayName("Nope");
  EXPECT_EQ(RunPipeline(map), 0);
  EXPECT_TRUE(observer->HasError("no point array 'Nope'")) << observer->AllErrors();
  map->ClearArrayNames();
  ring.pop_back();
  map->SetSourceAnchorsData(MakePointCloud(ring));
  EXPECT_EQ(RunPipeline(map), 0);
  EXPECT_TRUE(observer->HasError("6 anchors but the source has 5")) << observer->AllErrors();
}
