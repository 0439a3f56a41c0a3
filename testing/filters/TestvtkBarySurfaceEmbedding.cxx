// vtkBarySurfaceEmbedding: the filter over bary::euclidean_embedding: its arrays, its results,
// and the surfaces and settings it refuses.
#include "vtkBarySurfaceEmbedding.h"

#include "filters_test_utils.h"
#include "surface_test_utils.h"

#include "vtkBaryConversion.h"
#include "vtkBarySurfaceData.h"

#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"

#include "core/surface/euclidean_embedding.h"

using namespace barylab_test;

namespace
{

struct Embed
{
  vtkNew<vtkBarySurfaceEmbedding> Filter;
  vtkNew<ErrorObserver> Observer;
  explicit Embed(vtkPolyData* surface)
  {
    this->Filter->SetInputData(surface);
    this->Observer->Attach(this->Filter);
  }
  int Run() { return RunPipeline(this->Filter); }
};

} // namespace

TEST(vtkBarySurfaceEmbedding, ArraysAreTheCoreEmbedding)
{
  auto sphere = Sphere(24, 16);
  Embed e(sphere);
  e.Filter->SetNumberOfLandmarks(150);
  e.Filter->SetDimension(6);
  ASSERT_EQ(e.Run(), 1) << e.Observer->AllErrors();
  vtkPolyData* out = e.Filter->GetOutput();
  vtkDataArray* E = out->GetPointData()->GetArray("Embedding");
  ASSERT_NE(E, nullptr);
  EXPECT_EQ(E->GetNumberOfComponents(), 6);
  EXPECT_EQ(E->GetNumberOfTuples(), sphere->GetNumberOfPoints());
  EXPECT_EQ(out->GetNumberOfPolys(), sphere->GetNumberOfPolys());
  auto* landmarks = vtkIdTypeArray::SafeDownCast(out->GetFieldData()->GetArray("Landmarks"));
  ASSERT_NE(landmarks, nullptr);
  EXPECT_EQ(landmarks->GetNumberOfTuples(), 150);
  ASSERT_NE(out->GetFieldData()->GetArray("EmbeddingQuality"), nullptr);

  // The same computation through core.
  bary::EmbeddingOptions o;
  o.landmarks = 150;
  o.dimension = 6;
  const bary::EmbeddingResult r =
    bary::euclidean_embedding(vtkBarySurfaceData::ToSurfaceMesh(sphere), o);
  EXPECT_TRUE(vtkBaryConversion::ArrayToMatrix(E).cwiseEqual(r.E).all());
  EXPECT_EQ(e.Filter->GetSMACOFIterations(), r.smacof_iterations);
  EXPECT_DOUBLE_EQ(e.Filter->GetMeanRelativeError(), r.quality.mean_relative_error);
  EXPECT_GT(e.Filter->GetNumberOfStages(), 4);
  EXPECT_STREQ(e.Filter->GetStageName(0), "landmarks");
}

TEST(vtkBarySurfaceEmbedding, RefusesWhatItCannotEmbed)
{
  {
    vtkNew<vtkPlaneSource> quads;
    quads->SetResolution(4, 4);
    quads->Update();
    Embed e(quads->GetOutput());
    EXPECT_EQ(e.Run(), 0);
    EXPECT_TRUE(e.Observer->HasError("polygon 0 of the surface has 4 points")) << e.Observer->AllErrors();
  }
  {
    auto square = FlatSquare(6);
    Embed e(square);
    e.Filter->SetDimension(1);
    EXPECT_EQ(e.Run(), 0);
    EXPECT_TRUE(e.Observer->HasError("dimension must be in [2, 64]")) << e.Observer->AllErrors();
  }
  {
    vtkNew<vtkPolyData> empty;
    Embed e(empty);
    EXPECT_EQ(e.Run(), 0);
    EXPECT_TRUE(e.Observer->HasError("no points")) << e.Observer->AllErrors();
  }
  {
    // Two squares side by side: two pieces.
    auto a = FlatSquare(3);
    vtkNew<vtkPolyData> two;
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> polys;
    for (int copy = 0; copy < 2; ++copy)
    {
      for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
      {
        double x[3];
        a->GetPoint(i, x);
        points->InsertNextPoint(x[0] + 3 * copy, x[1], x[2]);
      }
      for (vtkIdType c = 0; c < a->GetNumberOfCells(); ++c)
      {
        vtkIdType ids[3];
        for (int k = 0; k < 3; ++k)
          ids[k] = a->GetCell(c)->GetPointId(k) + copy * a->GetNumberOfPoints();
        polys->InsertNextCell(3, ids);
      }
    }
    two->SetPoints(points);
    two->SetPolys(polys);
    Embed e(two);
    EXPECT_EQ(e.Run(), 0);
    EXPECT_TRUE(e.Observer->HasError("2 connected pieces")) << e.Observer->AllErrors();
  }
}
