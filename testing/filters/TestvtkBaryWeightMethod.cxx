// vtkBaryWeightMethod: its properties are views of the core settings table (defaults, clamping
// to the table's ranges, non-finite values refused), PrintSelf lists every setting, the
// settings hash follows the settings (not the thread count), and one method object shared by
// vtkBaryCoordinates and vtkBaryCageDeformation drives both (modification times, the cache).

#include "vtkBaryWeightMethod.h"

#include "vtkBaryCageDeformation.h"
#include "vtkBaryCoordinates.h"
#include "filters_test_utils.h"

#include "core/coordinates/weight_methods.h"

#include "vtkDoubleArray.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

using namespace barylab_test;

TEST(vtkBaryWeightMethod, PropertiesAreTheTablesSettings)
{
  vtkNew<vtkBaryWeightMethod> m;
  const bary::WeightsSettings defaults;
  EXPECT_EQ(m->GetMethod(), vtkBaryWeightMethod::MEAN_VALUE);
  EXPECT_EQ(m->GetBoundaryTolerance(), defaults.boundary_tolerance);
  EXPECT_EQ(m->GetLBCPrimalTolerance(), defaults.lbc_primal_tolerance);
  EXPECT_EQ(m->GetLBCMaximumIterations(), defaults.lbc_max_iterations);
  EXPECT_FALSE(m->GetBBWFast());
  EXPECT_FALSE(m->GetLBCUnconstrained());
  // every row of the table is reachable by key and reads back the default
  for (const bary::SettingField& f : bary::weights_setting_fields())
  {
    if (f.kind != bary::SettingField::Kind::Numbers)
    {
      EXPECT_EQ(m->GetSetting(f.key.c_str()), f.default_value()) << f.key;
    }
  }
  // clamped to the table's range, as vtkSetClampMacro does
  m->SetLBCPrimalTolerance(10.0);
  EXPECT_EQ(m->GetLBCPrimalTolerance(), bary::setting_field("lbc_primal_tolerance").maximum);
  m->SetLambda(0.5);
  EXPECT_EQ(m->GetLambda(), bary::setting_field("lambda").minimum);
  m->SetCageDimension(1);
  EXPECT_TRUE(m->GetCageDimension() == 0 || m->GetCageDimension() == 2) << "an allowed value";
  m->SetMethod(vtkBaryWeightMethod::NUMBER_OF_METHODS + 3);
  EXPECT_EQ(m->GetMethod(), vtkBaryWeightMethod::NUMBER_OF_METHODS - 1);
  EXPECT_TRUE(m->SetMethodByName("harmonic"));
  EXPECT_EQ(m->GetMethod(), vtkBaryWeightMethod::HARMONIC);
  EXPECT_FALSE(m->SetMethodByName("nope"));
  EXPECT_EQ(m->GetMethod(), vtkBaryWeightMethod::HARMONIC);
  EXPECT_STREQ(vtkBaryWeightMethod::GetMethodName(vtkBaryWeightMethod::LBC), "lbc");
  EXPECT_TRUE(vtkBaryWeightMethod::IsPointBased(vtkBaryWeightMethod::S_CELESTIAL));
  EXPECT_FALSE(vtkBaryWeightMethod::IsPointBased(vtkBaryWeightMethod::BBW));
}

TEST(vtkBaryWeightMethod, NonFiniteAndUnknownAreRefused)
{
  vtkNew<vtkBaryWeightMethod> m;
  vtkNew<ErrorObserver> observer;
  m->AddObserver(vtkCommand::ErrorEvent, observer);
  const vtkMTimeType before = m->GetMTime();
  m->SetLBCDualTolerance(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(m->GetLBCDualTolerance(), bary::WeightsSettings{}.lbc_dual_tolerance);
  EXPECT_TRUE(observer->HasError("setting 'lbc_dual_tolerance'")) << observer->AllErrors();
  m->SetSetting("nope", 1.0);
  EXPECT_TRUE(observer->HasError("unknown setting 'nope'")) << observer->AllErrors();
  EXPECT_EQ(m->GetMTime(), before) << "nothing changed";
  EXPECT_TRUE(std::isnan(m->GetSetting("nope")));
}

TEST(vtkBaryWeightMethod, PrintSelfListsEverySetting)
{
  vtkNew<vtkBaryWeightMethod> m;
  m->SetMethodToLBC();
  m->SetOutsidePolicy(vtkBaryWeightMethod::OUTSIDE_NAN);
  std::ostringstream out;
  m->Print(out);
  const std::string text = out.str();
  EXPECT_NE(text.find("Method: lbc"), std::string::npos) << text;
  EXPECT_NE(text.find("OutsidePolicy: nan"), std::string::npos) << text;
  for (const bary::SettingField& f : bary::weights_setting_fields())
    EXPECT_NE(text.find(f.property + ": "), std::string::npos) << f.property;
}

TEST(vtkBaryWeightMethod, HashFollowsTheSettingsButNotTheThreads)
{
  vtkNew<vtkBaryWeightMethod> m;
  const auto h0 = m->GetSettingsHash();
  m->SetNumberOfThreads(3);
  EXPECT_EQ(m->GetSettingsHash(), h0);
  m->SetTargetNumberOfCells(1234);
  const auto h1 = m->GetSettingsHash();
  EXPECT_NE(h1, h0);
  vtkNew<vtkDoubleArray> s;
  s->InsertNextValue(1.0);
  m->SetUserWeights(s);
  const auto h2 = m->GetSettingsHash();
  EXPECT_NE(h2, h1);
  s->SetValue(0, 2.0); // the array's values count
  EXPECT_NE(m->GetSettingsHash(), h2);
}

TEST(vtkBaryWeightMethod, OneMethodSharedByTwoFilters)
{
  vtkNew<vtkBaryWeightMethod> method;
  vtkNew<vtkBaryCoordinates> coords;
  vtkNew<vtkBaryCageDeformation> deform;
  coords->SetWeightMethod(method);
  deform->SetWeightMethod(method);
  EXPECT_EQ(coords->GetWeightMethod(), method.Get());
  coords->SetWeightMethod(nullptr); // refused: a filter always has a method
  EXPECT_EQ(coords->GetWeightMethod(), method.Get());

  auto cube = MakeCube();
  auto model = MakePointCloud({ { 0.1, 0.2, -0.3 }, { -0.5, 0.4, 0.2 } });
  coords->SetInputData(0, model);
  coords->SetCageData(cube);
  deform->SetInputData(0, model);
  deform->SetRestCageData(cube);
  deform->SetDeformedCageData(cube);
  deform->UseInputWeightsOff();
  ASSERT_EQ(RunPipeline(coords), 1);
  ASSERT_EQ(RunPipeline(deform), 1);
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 1);
  const vtkMTimeType t = coords->GetMTime();
  // a setting changed on the shared object reaches both filters
  method->SetBoundaryTolerance(1e-8);
  EXPECT_GT(coords->GetMTime(), t);
  ASSERT_EQ(RunPipeline(deform), 1);
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 2) << "new settings: weights recomputed";
  method->SetNumberOfThreads(1);
  ASSERT_EQ(RunPipeline(deform), 1);
  EXPECT_EQ(deform->GetNumberOfWeightComputations(), 2) << "the thread count changes no weight";
}
