// TestBaryLabParaViewPlugin <BaryLab plugin .so> <data folder> [<output folder>]
//
// Loads the BaryLab plugin into ParaView's server manager (a built-in session, as the paraview
// client's, with no Python: python3-paraview cannot be installed beside python3-vtk9), creates
// its proxies through vtkSMSessionProxyManager as the GUI does, updates pipelines and checks the
// results' mathematical properties against references computed here:
// - every proxy of the plugin's XML exists, and the XML's defaults are the classes';
// - the weight method's properties are BaryLab's settings table (core/coordinates/
//   weight_methods.h): one property per setting, with its default, and a value set on the
//   proxy reaches the VTK object;
// - File > Open's reader factory picks the plugin's reader for .off and .tgf;
// - mean value coordinates of the kidney (data/model3d.off) w.r.t. its cage (data/cage3d.obj),
//   both read by the plugin's reader: partition of unity and linear precision to 1e-12;
//   harmonic coordinates on a coarse mesh: the same to 1e-9;
// - cage deformation with the posed cage equals sum_i w_i c'_i computed here from the weights,
//   and the rest cage reproduces the model; linear blend skinning with one rigid motion;
// - reduce weights (K and row sums from the dense weights), locality statistics (Q(1) = 1 for
//   weights that sum to one; P(t) counted here), cage mesher (the tetrahedra's volume is the
//   cage's, by the divergence theorem here);
// - the .off writer's file reads back exactly;
// - weighted average (the weights from its Weights input's array, point data or a table's
//   rows): indicator weights give back their anchors (1e-9), the properties reach the filter, a
//   missing weights array is an error;
// - spline edit (one edit as properties; two in a chain): a translated anchor moves by exactly
//   `by`, a rotated one (named by its near position) lands on its rotation, the C1 residual
//   (field data Residual) stays below 1e-9, an edit naming no anchor is an error;
// - bad input (a missing file, an open cage) fails with an error, not a crash.
#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkClientServerInterpreter.h"
#include "vtkClientServerInterpreterInitializer.h"
#include "vtkClientServerStream.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkDataSet.h"
#include "vtkIdList.h"
#include "vtkInitializationHelper.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProcessModule.h"
#include "vtkSMParaViewPipelineController.h"
#include "vtkSMPluginManager.h"
#include "vtkSMReaderFactory.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMPropertyIterator.h"
#include "vtkSMStringVectorProperty.h"
#include "vtkSMVectorProperty.h"
#include "vtkSMProxyManager.h"
#include "vtkSMSession.h"
#include "vtkSMSessionProxyManager.h"
#include "vtkSMSourceProxy.h"
#include "vtkSMWriterProxy.h"
#include "vtkSmartPointer.h"
#include "vtkTable.h"
#include "vtkTetra.h"
#include "vtkUnstructuredGrid.h"
#include "vtkXMLPolyDataWriter.h"

#include "vtkBaryCoordinates.h"
#include "vtkBaryPVSplineEdit.h"
#include "vtkBaryPVWeightedAverage.h"
#include "vtkBaryWeightMethod.h"

#include "core/coordinates/weight_methods.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace
{
int failures = 0;
std::string outputDir = "."; ///< where the writer's file goes (argv[3])

/// Every proxy of the plugin's XML.
const char* const kProxies[][2] = { { "filters", "BaryCoordinates" },
  { "filters", "BaryCageDeformation" }, { "filters", "BaryReduceWeights" },
  { "filters", "BaryLocalityStatistics" }, { "filters", "BaryCageMesher" },
  { "filters", "BaryLinearBlendSkinning" }, { "filters", "BarySurfaceEmbedding" }, { "filters", "BarySurfaceWeights" },
  { "filters", "BarySurfaceCurve" }, { "filters", "BarySurfaceRemesh" },
  { "filters", "BarySurfaceCorrespondence" }, { "filters", "BarySplineSource" },
  { "filters", "BarySplineDeform" }, { "filters", "BaryWeightedAverage" },
  { "filters", "BarySplineEdit" }, { "sources", "BaryFileReader" },
  { "writers", "BaryOFFWriter" }, { "barylab_weight_methods", "WeightMethod" } };

void check(bool ok, const std::string& what)
{
  std::cout << (ok ? "ok   " : "FAIL ") << what << "\n";
  if (!ok)
    ++failures;
}

struct ErrorCounter
{
  int errors = 0;
  std::string messages; ///< the errors' texts
  static void Count(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* self = static_cast<ErrorCounter*>(clientData);
    ++self->errors;
    if (callData)
      self->messages += static_cast<const char*>(callData);
  }
};

class Pipeline
{
public:
  explicit Pipeline(vtkSMSessionProxyManager* pxm)
    : Pxm(pxm)
  {
  }

  vtkSMSourceProxy* Create(const char* group, const char* name)
  {
    vtkSmartPointer<vtkSMProxy> proxy;
    proxy.TakeReference(this->Pxm->NewProxy(group, name));
    auto* source = vtkSMSourceProxy::SafeDownCast(proxy);
    if (source)
    {
      this->Controller->PreInitializeProxy(source);
      this->Proxies.push_back(proxy);
    }
    return source;
  }

  /// Finishes the proxy as the GUI's Apply does (domain defaults, registration) and updates it.
  vtkDataObject* Update(vtkSMSourceProxy* proxy, ErrorCounter* errors = nullptr, int port = 0)
  {
    proxy->UpdateVTKObjects();
    this->Controller->PostInitializeProxy(proxy);
    this->Controller->RegisterPipelineProxy(proxy);
    auto* algorithm = vtkAlgorithm::SafeDownCast(proxy->GetClientSideObject());
    vtkNew<vtkCallbackCommand> observer;
    if (errors)
    {
      observer->SetCallback(&ErrorCounter::Count);
      observer->SetClientData(errors);
      algorithm->AddObserver(vtkCommand::ErrorEvent, observer);
    }
    proxy->UpdatePipeline();
    if (errors)
      algorithm->RemoveObserver(observer);
    return algorithm->GetOutputDataObject(port);
  }

  vtkNew<vtkSMParaViewPipelineController> Controller;
  vtkSMSessionProxyManager* Pxm;

private:
  std::vector<vtkSmartPointer<vtkSMProxy>> Proxies;
};

double Diameter(vtkDataSet* data)
{
  double b[6];
  data->GetBounds(b);
  return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
    (b[5] - b[4]) * (b[5] - b[4]));
}

/// Largest |sum_i w_i - 1| and largest |sum_i w_i c_i - x| over the points.
void WeightErrors(vtkDataSet* points, vtkDataArray* weights, vtkDataSet* cage, double* partition,
  double* reproduction)
{
  *partition = 0.0;
  *reproduction = 0.0;
  for (vtkIdType p = 0; p < points->GetNumberOfPoints(); ++p)
  {
    double sum = 0.0, x[3] = { 0, 0, 0 }, point[3];
    for (int i = 0; i < weights->GetNumberOfComponents(); ++i)
    {
      const double w = weights->GetComponent(p, i);
      double c[3];
      cage->GetPoint(i, c);
      sum += w;
      for (int k = 0; k < 3; ++k)
        x[k] += w * c[k];
    }
    points->GetPoint(p, point);
    *partition = std::max(*partition, std::abs(sum - 1.0));
    for (int k = 0; k < 3; ++k)
      *reproduction = std::max(*reproduction, std::abs(x[k] - point[k]));
  }
}

/// Volume enclosed by a closed, outward-oriented triangle surface (divergence theorem).
double EnclosedVolume(vtkPolyData* surface)
{
  double volume = 0.0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    surface->GetCellPoints(c, ids);
    double a[3], b[3], d[3];
    surface->GetPoint(ids->GetId(0), a);
    surface->GetPoint(ids->GetId(1), b);
    surface->GetPoint(ids->GetId(2), d);
    volume += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
                a[2] * (b[0] * d[1] - b[1] * d[0])) /
      6.0;
  }
  return volume;
}

double TetrahedraVolume(vtkUnstructuredGrid* grid)
{
  double volume = 0.0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
  {
    vtkCell* cell = grid->GetCell(c);
    if (cell->GetCellType() != VTK_TETRA)
      continue;
    double p[4][3];
    for (int k = 0; k < 4; ++k)
      cell->GetPoints()->GetPoint(k, p[k]);
    volume += std::abs(vtkTetra::ComputeVolume(p[0], p[1], p[2], p[3]));
  }
  return volume;
}

void CheckPluginProxies(vtkSMSessionProxyManager* pxm)
{
  for (const auto& p : kProxies)
  {
    vtkSmartPointer<vtkSMProxy> proxy;
    proxy.TakeReference(pxm->NewProxy(p[0], p[1]));
    check(proxy != nullptr, std::string("proxy ") + p[0] + "/" + p[1] + " exists");
  }
}


/// The XML's default of every one-element property of the plugin's hand-written proxies equals
/// what the VTK class's getter returns on a new object (the class, which takes its defaults
/// from the core's option structs, is the one place of a default; the XML's copy is checked
/// here). The weight method's properties are generated from the table (CheckSettingsTable).
void CheckDefaults(vtkSMSessionProxyManager* pxm)
{
  vtkClientServerInterpreter* interpreter =
    vtkClientServerInterpreterInitializer::GetGlobalInterpreter();
  int compared = 0, differ = 0;
  for (const auto& p : kProxies)
  {
    vtkSmartPointer<vtkSMProxy> proxy;
    proxy.TakeReference(pxm->NewProxy(p[0], p[1]));
    if (!proxy || std::string(p[1]) == "WeightMethod")
      continue;
    vtkSmartPointer<vtkObjectBase> object;
    object.TakeReference(interpreter->NewInstance(proxy->GetVTKClassName()));
    vtkNew<vtkSMPropertyIterator> it;
    it->SetProxy(proxy);
    it->SetTraverseSubProxies(0);
    for (it->Begin(); !it->IsAtEnd(); it->Next())
    {
      auto* property = vtkSMVectorProperty::SafeDownCast(it->GetProperty());
      const char* command = property ? property->GetCommand() : nullptr;
      if (!command || std::string(command).rfind("Set", 0) != 0 ||
        property->GetNumberOfElements() != 1 || property->GetInformationOnly() ||
        std::string(it->GetKey()) == "FileName")
        continue;
      // the weight method's properties, exposed from its sub-proxy: CheckSettingsTable's
      const std::string name = proxy->GetXMLName();
      if ((name == "BaryCoordinates" || name == "BaryCageDeformation") &&
        (bary::setting_field_of_property(it->GetKey()) || std::string(it->GetKey()) == "Method"))
        continue;
      vtkClientServerStream stream;
      stream << vtkClientServerStream::Invoke << object << ("Get" + std::string(command + 3))
             << vtkClientServerStream::End;
      interpreter->ProcessStream(stream);
      const vtkClientServerStream& result = interpreter->GetLastResult();
      std::string xml, cls;
      if (vtkSMStringVectorProperty::SafeDownCast(property))
      {
        const char* text = nullptr;
        xml = vtkSMPropertyHelper(property).GetAsString();
        cls = result.GetArgument(0, 0, &text) && text ? text : "(no value)";
      }
      else
      {
        double value = 0.0;
        bool flag = false;
        xml = std::to_string(vtkSMPropertyHelper(property).GetAsDouble());
        if (result.GetArgument(0, 0, &value))
          cls = std::to_string(value);
        else if (result.GetArgument(0, 0, &flag)) // vtkGetMacro of a bool
          cls = std::to_string(flag ? 1.0 : 0.0);
        else
          cls = "(no value)";
      }
      ++compared;
      if (xml != cls)
      {
        ++differ;
        std::cout << "     " << p[1] << "." << it->GetKey() << ": XML " << xml << ", class "
                  << cls << "\n";
      }
    }
  }
  std::cout << "     " << compared << " defaults compared\n";
  check(compared > 40 && differ == 0,
    "the XML's defaults are the classes' (every one-element property)");
}

/// File > Open: ParaView's reader factory picks the plugin's reader for the formats it lacks
/// (it asks the reader's CanReadFile through the client-server layer, as the GUI does).
void CheckReaderFactory(vtkSMProxyManager* proxyManager, const std::string& data)
{
  vtkSMReaderFactory* factory = proxyManager->GetReaderFactory();
  vtkSMSession* session = proxyManager->GetActiveSession();
  for (const char* file : { "model3d.off", "heart.off", "skeleton2d.tgf" })
  {
    const std::string path = data + "/" + file;
    const bool found = factory->CanReadFile(path.c_str(), session);
    const std::string reader = found && factory->GetReaderName() ? factory->GetReaderName() : "";
    check(found && reader == "BaryFileReader",
      std::string("File > Open finds the plugin's reader for ") + file + " (" +
        (reader.empty() ? "none" : reader) + ")");
  }
}

void CheckSettingsTable(Pipeline& pipeline)
{
  vtkSMSourceProxy* proxy = pipeline.Create("filters", "BaryCoordinates");
  int missing = 0, wrong_default = 0;
  for (const bary::SettingField& f : bary::weights_setting_fields())
  {
    vtkSMProperty* property = proxy->GetProperty(f.property.c_str());
    if (!property)
    {
      ++missing;
      std::cout << "     no property " << f.property << "\n";
      continue;
    }
    if (f.kind == bary::SettingField::Kind::Numbers)
    {
      // a list (the user weights), empty by default
      if (vtkSMPropertyHelper(property).GetNumberOfElements() != 0)
        ++wrong_default;
      continue;
    }
    const double value = vtkSMPropertyHelper(property).GetAsDouble();
    if (value != f.default_value())
    {
      ++wrong_default;
      std::cout << "     " << f.property << " default " << value << ", table "
                << f.default_value() << "\n";
    }
  }
  check(missing == 0, "every setting of the table is a property of BaryCoordinates");
  check(wrong_default == 0, "every property's default is the table's");
  check(vtkSMPropertyHelper(proxy, "Method").GetAsInt() ==
      static_cast<int>(bary::WeightsSettings{}.method),
    "Method's default is the table's");

  // A value set on the proxy reaches the filter's vtkBaryWeightMethod.
  vtkSMPropertyHelper(proxy, "Method").Set(static_cast<int>(bary::MethodId::LBC));
  vtkSMPropertyHelper(proxy, "LBCPrimalTolerance").Set(2.5e-7);
  vtkSMPropertyHelper(proxy, "LBCStopping").Set(0);
  const double userWeights[3] = { 0.5, 1.5, 2.0 };
  vtkSMPropertyHelper(proxy, "UserWeights").Set(userWeights, 3);
  proxy->UpdateVTKObjects();
  auto* filter = vtkBaryCoordinates::SafeDownCast(proxy->GetClientSideObject());
  vtkDataArray* given = filter ? filter->GetWeightMethod()->GetUserWeights() : nullptr;
  check(given && given->GetNumberOfTuples() == 3 && given->GetComponent(0, 0) == 0.5 &&
      given->GetComponent(1, 0) == 1.5 && given->GetComponent(2, 0) == 2.0,
    "the T-celestial user weights set as a list on the proxy reach the weight method");
  check(filter && filter->GetWeightMethod()->GetMethod() == vtkBaryWeightMethod::LBC &&
      filter->GetWeightMethod()->GetLBCPrimalTolerance() == 2.5e-7 &&
      filter->GetWeightMethod()->GetLBCStopping() == vtkBaryWeightMethod::LBC_STOPPING_PAPER,
    "properties set on the proxy reach the filter's weight method");
}

vtkSMSourceProxy* Reader(Pipeline& pipeline, const std::string& path)
{
  vtkSMSourceProxy* reader = pipeline.Create("sources", "BaryFileReader");
  vtkSMPropertyHelper(reader, "FileName").Set(path.c_str());
  return reader;
}

void CheckWeightsAndDeformation(Pipeline& pipeline, const std::string& data)
{
  vtkSMSourceProxy* model = Reader(pipeline, data + "/model3d.off");
  vtkSMSourceProxy* cage = Reader(pipeline, data + "/cage3d.obj");
  vtkSMSourceProxy* posed = Reader(pipeline, data + "/cage3d_posed.obj");
  auto* modelData = vtkDataSet::SafeDownCast(pipeline.Update(model));
  auto* cageData = vtkPolyData::SafeDownCast(pipeline.Update(cage));
  auto* posedData = vtkDataSet::SafeDownCast(pipeline.Update(posed));
  check(modelData && modelData->GetNumberOfPoints() == 2562 && modelData->GetNumberOfCells() == 5120,
    "the reader reads data/model3d.off (2562 points, 5120 triangles)");
  check(cageData && cageData->GetNumberOfPoints() == 72 && posedData &&
      posedData->GetNumberOfPoints() == 72,
    "the reader reads the cages (72 points each)");
  if (!modelData || !cageData || !posedData)
    return;

  // The .off writer: what it writes reads back as the same points (17 significant digits).
  const std::string written = outputDir + "/paraview_plugin_model.off";
  std::remove(written.c_str());
  vtkSmartPointer<vtkSMProxy> writerProxy;
  writerProxy.TakeReference(pipeline.Pxm->NewProxy("writers", "BaryOFFWriter"));
  auto* writer = vtkSMWriterProxy::SafeDownCast(writerProxy);
  if (writer)
  {
    vtkSMPropertyHelper(writer, "Input").Set(model, 0);
    vtkSMPropertyHelper(writer, "FileName").Set(written.c_str());
    writer->UpdateVTKObjects();
    writer->UpdatePipeline();
  }
  vtkSMSourceProxy* back = Reader(pipeline, written);
  auto* backData = vtkDataSet::SafeDownCast(pipeline.Update(back));
  double roundTrip = backData && backData->GetNumberOfPoints() == modelData->GetNumberOfPoints() &&
      backData->GetNumberOfCells() == modelData->GetNumberOfCells()
    ? 0.0
    : 1.0;
  for (vtkIdType p = 0; roundTrip == 0.0 && p < backData->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    backData->GetPoint(p, a);
    modelData->GetPoint(p, b);
    for (int k = 0; k < 3; ++k)
      roundTrip = std::max(roundTrip, std::abs(a[k] - b[k]));
  }
  check(writer && roundTrip == 0.0,
    "the .off writer's file reads back with the same points and cells, exactly");

  // Mean value coordinates (the default method).
  vtkSMSourceProxy* mvc = pipeline.Create("filters", "BaryCoordinates");
  vtkSMPropertyHelper(mvc, "Input").Set(model, 0);
  vtkSMPropertyHelper(mvc, "Cage").Set(cage, 0);
  ErrorCounter errors;
  auto* weighted = vtkDataSet::SafeDownCast(pipeline.Update(mvc, &errors));
  vtkDataArray* weights = weighted ? weighted->GetPointData()->GetArray("Weights") : nullptr;
  check(errors.errors == 0 && weights && weights->GetNumberOfComponents() == 72 &&
      weights->GetNumberOfTuples() == 2562,
    "mean value coordinates: a Weights array of 72 components on every point");
  if (!weights)
    return;
  double partition, reproduction;
  WeightErrors(weighted, weights, cageData, &partition, &reproduction);
  std::cout << "     mvc: partition of unity error " << partition << ", reproduction error "
            << reproduction << " (diameter " << Diameter(cageData) << ")\n";
  check(partition <= 1e-12, "mean value coordinates: partition of unity to 1e-12");
  check(reproduction <= 1e-12 * Diameter(cageData),
    "mean value coordinates: linear precision to 1e-12 of the cage's diameter");

  // Harmonic coordinates on a coarse mesh of the cage (the mesh properties from the table).
  vtkSMSourceProxy* harmonic = pipeline.Create("filters", "BaryCoordinates");
  vtkSMPropertyHelper(harmonic, "Input").Set(model, 0);
  vtkSMPropertyHelper(harmonic, "Cage").Set(cage, 0);
  vtkSMPropertyHelper(harmonic, "Method").Set(static_cast<int>(bary::MethodId::Harmonic));
  vtkSMPropertyHelper(harmonic, "TargetNumberOfCells").Set(3000);
  auto* harmonicData = vtkDataSet::SafeDownCast(pipeline.Update(harmonic));
  vtkDataArray* hw = harmonicData ? harmonicData->GetPointData()->GetArray("Weights") : nullptr;
  if (hw)
  {
    double minimum = 0.0;
    for (vtkIdType p = 0; p < hw->GetNumberOfTuples(); ++p)
      for (int i = 0; i < hw->GetNumberOfComponents(); ++i)
        minimum = std::min(minimum, hw->GetComponent(p, i));
    WeightErrors(harmonicData, hw, cageData, &partition, &reproduction);
    // Linear finite elements reproduce linear functions exactly (the cage's boundary values are
    // linear on its faces), so partition of unity and linear precision hold to the solver's
    // precision; non-negativity does not hold exactly on a coarse mesh (no discrete maximum
    // principle for obtuse tetrahedra), so the minimum is only reported.
    std::cout << "     harmonic: partition of unity error " << partition << ", reproduction error "
              << reproduction << ", minimum weight " << minimum << "\n";
    check(hw->GetNumberOfComponents() == 72 && partition <= 1e-9 &&
        reproduction <= 1e-9 * Diameter(cageData),
      "harmonic coordinates: partition of unity and linear precision (1e-9)");
  }
  else
    check(false, "harmonic coordinates: a Weights array");

  // Cage deformation with the weights the model carries (from BaryCoordinates).
  vtkSMSourceProxy* deform = pipeline.Create("filters", "BaryCageDeformation");
  vtkSMPropertyHelper(deform, "Input").Set(mvc, 0);
  vtkSMPropertyHelper(deform, "RestCage").Set(cage, 0);
  vtkSMPropertyHelper(deform, "DeformedCage").Set(posed, 0);
  auto* deformed = vtkPointSet::SafeDownCast(pipeline.Update(deform));
  double deviation = deformed ? 0.0 : 1.0;
  for (vtkIdType p = 0; deformed && p < deformed->GetNumberOfPoints(); ++p)
  {
    double expected[3] = { 0, 0, 0 }, x[3];
    for (int i = 0; i < 72; ++i)
    {
      double c[3];
      posedData->GetPoint(i, c);
      for (int k = 0; k < 3; ++k)
        expected[k] += weights->GetComponent(p, i) * c[k];
    }
    deformed->GetPoint(p, x);
    for (int k = 0; k < 3; ++k)
      deviation = std::max(deviation, std::abs(x[k] - expected[k]));
  }
  std::cout << "     deformation: largest deviation from sum_i w_i c'_i " << deviation << "\n";
  check(deviation <= 1e-12, "cage deformation: x' = sum_i w_i c'_i to 1e-12");

  // The same filter computing its own weights, with the rest cage as the deformed one: identity.
  vtkSMSourceProxy* identity = pipeline.Create("filters", "BaryCageDeformation");
  vtkSMPropertyHelper(identity, "Input").Set(model, 0);
  vtkSMPropertyHelper(identity, "RestCage").Set(cage, 0);
  vtkSMPropertyHelper(identity, "DeformedCage").Set(cage, 0);
  auto* same = vtkPointSet::SafeDownCast(pipeline.Update(identity));
  deviation = same ? 0.0 : 1.0;
  for (vtkIdType p = 0; same && p < same->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    same->GetPoint(p, a);
    modelData->GetPoint(p, b);
    for (int k = 0; k < 3; ++k)
      deviation = std::max(deviation, std::abs(a[k] - b[k]));
  }
  check(deviation <= 1e-12 * Diameter(cageData),
    "cage deformation by the rest cage reproduces the model (1e-12 of the diameter)");

  // Linear blend skinning with one rigid motion on every handle moves every point by it (the
  // weights sum to one).
  vtkSMSourceProxy* skin = pipeline.Create("filters", "BaryLinearBlendSkinning");
  vtkSMPropertyHelper(skin, "Input").Set(mvc, 0);
  const double angle = 0.5, cs = std::cos(angle), sn = std::sin(angle);
  const double motion[12] = { cs, -sn, 0, 0.1, sn, cs, 0, -0.2, 0, 0, 1, 0.3 };
  std::vector<double> transforms;
  for (int handle = 0; handle < 72; ++handle)
    transforms.insert(transforms.end(), motion, motion + 12);
  vtkSMPropertyHelper(skin, "Transforms").Set(transforms.data(), static_cast<unsigned int>(transforms.size()));
  ErrorCounter skinErrors;
  auto* skinned = vtkPointSet::SafeDownCast(pipeline.Update(skin, &skinErrors));
  deviation = skinned && skinned->GetNumberOfPoints() == 2562 ? 0.0 : 1.0;
  for (vtkIdType p = 0; skinned && p < skinned->GetNumberOfPoints(); ++p)
  {
    double x[3], y[3];
    modelData->GetPoint(p, x);
    skinned->GetPoint(p, y);
    for (int r = 0; r < 3; ++r)
      deviation = std::max(deviation,
        std::abs(y[r] - (motion[4 * r] * x[0] + motion[4 * r + 1] * x[1] + motion[4 * r + 2] * x[2] + motion[4 * r + 3])));
  }
  check(skinErrors.errors == 0 && deviation <= 1e-12 * Diameter(cageData),
    "linear blend skinning: one rigid motion on all 72 handles moves the model by it (1e-12)");

  // Reduce weights (threshold 0.05): K, the compact arrays' width, is the largest number of
  // weights above the threshold at one point, counted here from the dense weights; each row of
  // kept weights sums to one (RowSum renormalisation).
  vtkSMSourceProxy* reduce = pipeline.Create("filters", "BaryReduceWeights");
  vtkSMPropertyHelper(reduce, "Input").Set(harmonic, 0);
  vtkSMPropertyHelper(reduce, "Threshold").Set(0.05);
  auto* reduced = vtkDataSet::SafeDownCast(pipeline.Update(reduce));
  vtkDataArray* values = reduced ? reduced->GetPointData()->GetArray("WeightsValues") : nullptr;
  int expectedK = 0;
  for (vtkIdType p = 0; hw && p < hw->GetNumberOfTuples(); ++p)
  {
    int kept = 0;
    for (int i = 0; i < hw->GetNumberOfComponents(); ++i)
      kept += hw->GetComponent(p, i) > 0.05 ? 1 : 0;
    expectedK = std::max(expectedK, kept);
  }
  double rowError = values ? 0.0 : 1.0;
  for (vtkIdType p = 0; values && p < values->GetNumberOfTuples(); ++p)
  {
    double sum = 0.0;
    for (int k = 0; k < values->GetNumberOfComponents(); ++k)
      sum += values->GetComponent(p, k);
    rowError = std::max(rowError, std::abs(sum - 1.0));
  }
  std::cout << "     reduce weights: K = " << (values ? values->GetNumberOfComponents() : -1)
            << " (counted: " << expectedK << "), largest row-sum error " << rowError << "\n";
  check(values && values->GetNumberOfComponents() == expectedK && rowError <= 1e-12,
    "reduce weights: K as counted from the dense weights, rows summing to 1 (1e-12)");

  // Locality statistics: Q(1) = 1 where the weights sum to one.
  vtkSMSourceProxy* locality = pipeline.Create("filters", "BaryLocalityStatistics");
  vtkSMPropertyHelper(locality, "Input").Set(harmonic, 0);
  auto* q = vtkTable::SafeDownCast(pipeline.Update(locality, nullptr, 1));
  vtkDataArray* qColumn = q ? vtkDataArray::SafeDownCast(q->GetColumnByName("Q")) : nullptr;
  check(qColumn && qColumn->GetNumberOfTuples() == 72 &&
      std::abs(qColumn->GetComponent(0, 0) - 1.0) <= 1e-12,
    "locality statistics: Q has 72 rows and Q(1) = 1");
  auto* pDefault = vtkTable::SafeDownCast(pipeline.Update(locality, nullptr, 0));
  check(pDefault && pDefault->GetNumberOfRows() == 26, "locality statistics: 26 default t values");

  // Own t values (the plugin's glue): P(t) at them, in increasing order, equal to the fraction
  // of the dense weights with |w_i| <= t counted here (every point counts the same: the input
  // is a curved triangle surface, not a domain mesh).
  vtkSMSourceProxy* ownT = pipeline.Create("filters", "BaryLocalityStatistics");
  vtkSMPropertyHelper(ownT, "Input").Set(harmonic, 0);
  const double ts[3] = { 1.0, 0.01, 0.1 };
  vtkSMPropertyHelper(ownT, "TValues").Set(ts, 3);
  auto* pt = vtkTable::SafeDownCast(pipeline.Update(ownT, nullptr, 0));
  vtkDataArray* tColumn = pt ? vtkDataArray::SafeDownCast(pt->GetColumnByName("t")) : nullptr;
  vtkDataArray* pColumn = pt ? vtkDataArray::SafeDownCast(pt->GetColumnByName("P")) : nullptr;
  bool ok = tColumn && pColumn && tColumn->GetNumberOfTuples() == 3;
  double largest = 0.0;
  for (int row = 0; ok && row < 3; ++row)
  {
    const double t = tColumn->GetComponent(row, 0);
    double counted = 0.0;
    for (vtkIdType p = 0; p < hw->GetNumberOfTuples(); ++p)
      for (int i = 0; i < 72; ++i)
        counted += std::abs(hw->GetComponent(p, i)) <= t ? 1.0 : 0.0;
    counted /= static_cast<double>(hw->GetNumberOfTuples()) * 72.0;
    largest = std::max(largest, std::abs(counted - pColumn->GetComponent(row, 0)));
    ok = ok && t == (row == 0 ? 0.01 : row == 1 ? 0.1 : 1.0);
  }
  std::cout << "     locality statistics: largest |P(t) - counted| " << largest << "\n";
  check(ok && largest <= 1e-12,
    "locality statistics with own t values: sorted, P(t) as counted from the weights");
}

/// Weighted average: a sphere embedded by Surface Embedding (all its 130 vertices landmarks),
/// four of its vertices as anchors and indicator weights, all from a .vtp file written here
/// (the anchors' points, point data IndicatorWeights: row q = e_{3-q}, and a decoy Weights: row
/// q = e_q) read by ParaView's XML reader.
/// Query q is then anchor 3 - q itself (Panozzo et al. 2013, §3.1: the weighted average of an
/// anchor's indicator weights is the anchor).
void CheckWeightedAverage(Pipeline& pipeline)
{
  vtkSMSourceProxy* sphere = pipeline.Create("sources", "SphereSource");
  vtkSMPropertyHelper(sphere, "ThetaResolution").Set(16);
  vtkSMPropertyHelper(sphere, "PhiResolution").Set(10);
  auto* sphereData = vtkPolyData::SafeDownCast(pipeline.Update(sphere));
  vtkSMSourceProxy* embed = pipeline.Create("filters", "BarySurfaceEmbedding");
  vtkSMPropertyHelper(embed, "Input").Set(sphere, 0);
  vtkSMPropertyHelper(embed, "Dimension").Set(4);
  pipeline.Update(embed);
  if (!sphereData || sphereData->GetNumberOfPoints() != 130)
  {
    check(false, "weighted average: the sphere source's 130 points");
    return;
  }
  const vtkIdType ids[4] = { 3, 40, 77, 120 };
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkDoubleArray> indicator;
  indicator->SetName("IndicatorWeights");
  indicator->SetNumberOfComponents(4);
  indicator->SetNumberOfTuples(4);
  indicator->Fill(0.0);
  for (int q = 0; q < 4; ++q)
  {
    points->InsertNextPoint(sphereData->GetPoint(ids[q]));
    indicator->SetComponent(q, 3 - q, 1.0);
  }
  // a decoy first: the identity (row q = e_q), named as the property's default; the filter must
  // take the array chosen by WeightsArrayName
  vtkNew<vtkDoubleArray> decoy;
  decoy->SetName("Weights");
  decoy->SetNumberOfComponents(4);
  decoy->SetNumberOfTuples(4);
  decoy->Fill(0.0);
  for (int q = 0; q < 4; ++q)
    decoy->SetComponent(q, q, 1.0);
  vtkNew<vtkPolyData> anchors;
  anchors->SetPoints(points);
  anchors->GetPointData()->AddArray(decoy);
  anchors->GetPointData()->AddArray(indicator);
  const std::string file = outputDir + "/weighted_average_anchors.vtp";
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(anchors);
  writer->SetFileName(file.c_str());
  writer->Write();
  vtkSMSourceProxy* reader = pipeline.Create("sources", "XMLPolyDataReader");
  vtkSMPropertyHelper(reader, "FileName").Set(file.c_str());
  pipeline.Update(reader);

  vtkSMSourceProxy* average = pipeline.Create("filters", "BaryWeightedAverage");
  vtkSMPropertyHelper(average, "Input").Set(embed, 0);
  vtkSMPropertyHelper(average, "Anchors").Set(reader, 0);
  vtkSMPropertyHelper(average, "Weights").Set(reader, 0);
  vtkSMPropertyHelper(average, "WeightsArrayName").Set("IndicatorWeights");
  vtkSMPropertyHelper(average, "WarmStart").Set(1);
  vtkSMPropertyHelper(average, "SurfaceTolerance").Set(0.002);
  ErrorCounter errors;
  auto* result = vtkPolyData::SafeDownCast(pipeline.Update(average, &errors));
  auto* filter = vtkBaryPVWeightedAverage::SafeDownCast(average->GetClientSideObject());
  check(filter && std::string(filter->GetWeightsArrayName()) == "IndicatorWeights" &&
      filter->GetWarmStart() && filter->GetSurfaceTolerance() == 0.002,
    "weighted average: properties set on the proxy reach the filter");
  double deviation = result && result->GetNumberOfPoints() == 4 && errors.errors == 0 ? 0.0 : 1.0;
  for (int q = 0; deviation < 1.0 && q < 4; ++q)
  {
    double x[3], a[3];
    result->GetPoint(q, x);
    points->GetPoint(3 - q, a);
    for (int k = 0; k < 3; ++k)
      deviation = std::max(deviation, std::abs(x[k] - a[k]));
  }
  std::cout << "     weighted average: largest distance of an indicator's average from its anchor "
            << deviation << "\n";
  check(deviation <= 1e-9,
    "weighted average: an anchor's indicator weights give back the anchor (1e-9)");

  // The same weights as a table's rows (ParaView's Extract Attributes makes the point data a
  // vtkTable), as a weights file read into a table would give them.
  vtkSMSourceProxy* table = pipeline.Create("filters", "AttributeDataToTableFilter");
  vtkSMPropertyHelper(table, "Input").Set(reader, 0);
  auto* tableData = vtkTable::SafeDownCast(pipeline.Update(table));
  vtkSMSourceProxy* fromTable = pipeline.Create("filters", "BaryWeightedAverage");
  vtkSMPropertyHelper(fromTable, "Input").Set(embed, 0);
  vtkSMPropertyHelper(fromTable, "Anchors").Set(reader, 0);
  vtkSMPropertyHelper(fromTable, "Weights").Set(table, 0);
  vtkSMPropertyHelper(fromTable, "WeightsArrayName").Set("IndicatorWeights");
  ErrorCounter tableErrors;
  auto* tableResult = vtkPolyData::SafeDownCast(pipeline.Update(fromTable, &tableErrors));
  deviation = tableData && tableResult && tableResult->GetNumberOfPoints() == 4 &&
      tableErrors.errors == 0 ? 0.0 : 1.0;
  for (int q = 0; deviation < 1.0 && q < 4; ++q)
  {
    double x[3], a[3];
    tableResult->GetPoint(q, x);
    points->GetPoint(3 - q, a);
    for (int k = 0; k < 3; ++k)
      deviation = std::max(deviation, std::abs(x[k] - a[k]));
  }
  check(deviation <= 1e-9,
    "weighted average: the same indicator weights as a table's rows give back the anchors (1e-9)");

  if (!filter)
    return;
  // the same proxy again, as a change in its panel and Apply do
  vtkSMPropertyHelper(average, "WeightsArrayName").Set("NoSuchArray");
  average->UpdateVTKObjects();
  ErrorCounter missing;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetCallback(&ErrorCounter::Count);
  observer->SetClientData(&missing);
  filter->AddObserver(vtkCommand::ErrorEvent, observer);
  average->UpdatePipeline();
  filter->RemoveObserver(observer);
  auto* none = vtkPolyData::SafeDownCast(filter->GetOutputDataObject(0));
  check(missing.errors > 0 && missing.messages.find("'NoSuchArray'") != std::string::npos &&
      (!none || none->GetNumberOfPoints() == 0),
    "weighted average: a weights array the Weights input lacks is an error naming it");
}

/// Spline edit: the identity spline of data/spline_domain.obj; a translation of the control point
/// nearest the origin (by its index, delta_max 2), then, in a second filter of the chain, a
/// rotation by 3 degrees about the origin of the control point nearest its new position (by
/// NearPositions). DECLeS moves anchors exactly (Rodrigues et al. 2014, §4) and keeps C1.
void CheckSplineEdit(Pipeline& pipeline, const std::string& data)
{
  vtkSMSourceProxy* domain = Reader(pipeline, data + "/spline_domain.obj");
  pipeline.Update(domain);
  vtkSMSourceProxy* source = pipeline.Create("filters", "BarySplineSource");
  vtkSMPropertyHelper(source, "Input").Set(domain, 0);
  auto* grid = vtkPointSet::SafeDownCast(pipeline.Update(source));
  if (!grid || grid->GetNumberOfPoints() == 0)
  {
    check(false, "spline edit: a spline grid");
    return;
  }
  int i = 0;
  double best = 1e300, x0[3];
  for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
  {
    double x[3];
    grid->GetPoint(p, x);
    if (x[0] * x[0] + x[1] * x[1] < best)
    {
      best = x[0] * x[0] + x[1] * x[1];
      i = static_cast<int>(p);
    }
  }
  grid->GetPoint(i, x0);

  vtkSMSourceProxy* translate = pipeline.Create("filters", "BarySplineEdit");
  vtkSMPropertyHelper(translate, "Input").Set(source, 0);
  vtkSMPropertyHelper(translate, "AnchorIndices").Set(&i, 1);
  const double by[2] = { 0.05, -0.02 };
  vtkSMPropertyHelper(translate, "By").Set(by, 2);
  vtkSMPropertyHelper(translate, "DeltaMax").Set(2);
  ErrorCounter errors;
  auto* moved = vtkPointSet::SafeDownCast(pipeline.Update(translate, &errors));
  auto* filter = vtkBaryPVSplineEdit::SafeDownCast(translate->GetClientSideObject());
  check(filter && filter->GetOperation() == vtkBaryPVSplineEdit::TRANSLATE &&
      filter->GetTarget() == vtkBarySplineEdit::XY && filter->GetDeltaMax() == 2 &&
      filter->GetBy()[0] == 0.05 && filter->GetBy()[1] == -0.02,
    "spline edit: properties set on the proxy reach the filter");
  auto residual = [](vtkPointSet* out) {
    vtkDataArray* r = out ? out->GetFieldData()->GetArray("Residual") : nullptr;
    return r && r->GetNumberOfTuples() == 1 ? r->GetComponent(0, 0) : 1.0;
  };
  double x1[3] = { 0, 0, 0 };
  int count = 0;
  if (moved && moved->GetNumberOfPoints() == grid->GetNumberOfPoints())
  {
    moved->GetPoint(i, x1);
    for (vtkIdType p = 0; p < grid->GetNumberOfPoints(); ++p)
    {
      double a[3], b[3];
      grid->GetPoint(p, a);
      moved->GetPoint(p, b);
      count += (a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) ? 1 : 0;
    }
  }
  const double error = std::max({ std::abs(x1[0] - x0[0] - by[0]),
    std::abs(x1[1] - x0[1] - by[1]), std::abs(x1[2] - x0[2]) });
  std::cout << "     spline edit: anchor " << i << " moved off by " << error << " from (0.05, -0.02); "
            << count << " of " << grid->GetNumberOfPoints() << " control points moved; residual "
            << residual(moved) << "\n";
  check(errors.errors == 0 && error <= 1e-15 && count > 1 && count < grid->GetNumberOfPoints() / 10,
    "spline edit: the anchor moves by exactly `by`, a few neighbours follow");
  check(residual(moved) < 1e-9, "spline edit: C1 residual below 1e-9");

  vtkSMSourceProxy* rotate = pipeline.Create("filters", "BarySplineEdit");
  vtkSMPropertyHelper(rotate, "Input").Set(translate, 0);
  vtkSMPropertyHelper(rotate, "Operation").Set(vtkBaryPVSplineEdit::ROTATE);
  const double near[2] = { x1[0], x1[1] };
  vtkSMPropertyHelper(rotate, "NearPositions").Set(near, 2);
  vtkSMPropertyHelper(rotate, "Angle").Set(3.0);
  auto* turned = vtkPointSet::SafeDownCast(pipeline.Update(rotate, &errors));
  const double a = 3.0 * M_PI / 180.0;
  double x2[3] = { 0, 0, 0 };
  if (turned && turned->GetNumberOfPoints() == grid->GetNumberOfPoints())
    turned->GetPoint(i, x2);
  const double turnError = std::max(std::abs(x2[0] - (std::cos(a) * x1[0] - std::sin(a) * x1[1])),
    std::abs(x2[1] - (std::sin(a) * x1[0] + std::cos(a) * x1[1])));
  std::cout << "     spline edit: rotated anchor off its rotation by " << turnError
            << "; residual " << residual(turned) << "\n";
  check(errors.errors == 0 && turnError <= 1e-12 && residual(turned) < 1e-9,
    "spline edit chained: the anchor nearest NearPositions turns by Angle about Center, C1 kept");

  vtkSMSourceProxy* nothing = pipeline.Create("filters", "BarySplineEdit");
  vtkSMPropertyHelper(nothing, "Input").Set(source, 0);
  ErrorCounter noAnchor;
  pipeline.Update(nothing, &noAnchor);
  std::cout << "     spline edit with no anchor: " << noAnchor.messages << "\n";
  check(noAnchor.errors > 0 && noAnchor.messages.find("at least one anchor") != std::string::npos,
    "spline edit: an edit naming no anchor is an error saying so");
}

void CheckMesherAndErrors(Pipeline& pipeline, const std::string& data)
{
  vtkSMSourceProxy* cage = Reader(pipeline, data + "/cage3d.obj");
  auto* cageData = vtkPolyData::SafeDownCast(pipeline.Update(cage));
  vtkSMSourceProxy* mesher = pipeline.Create("filters", "BaryCageMesher");
  vtkSMPropertyHelper(mesher, "Input").Set(cage, 0);
  vtkSMPropertyHelper(mesher, "TargetNumberOfCells").Set(2000);
  auto* mesh = vtkUnstructuredGrid::SafeDownCast(pipeline.Update(mesher));
  if (mesh && cageData)
  {
    const double expected = EnclosedVolume(cageData);
    const double volume = TetrahedraVolume(mesh);
    std::cout << "     mesher: " << mesh->GetNumberOfCells() << " tetrahedra, volume " << volume
              << " (cage " << expected << ")\n";
    check(mesh->GetNumberOfCells() > 0 && std::abs(volume - expected) <= 1e-9 * expected,
      "cage mesher: the tetrahedra fill the cage's volume (1e-9 relative)");
  }
  else
    check(false, "cage mesher: an unstructured grid");

  ErrorCounter missing;
  vtkSMSourceProxy* reader = Reader(pipeline, data + "/no_such_file.off");
  auto* none = vtkDataSet::SafeDownCast(pipeline.Update(reader, &missing));
  check(missing.errors > 0 && (!none || none->GetNumberOfPoints() == 0),
    "a missing file is an error with an empty output");

  // An open cage (one triangle less): the coordinates filter fails with an error.
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 1; c < cageData->GetNumberOfCells(); ++c)
  {
    cageData->GetCellPoints(c, ids);
    polys->InsertNextCell(ids);
  }
  vtkNew<vtkPolyData> openCage;
  openCage->SetPoints(cageData->GetPoints());
  openCage->SetPolys(polys);
  vtkNew<vtkBaryCoordinates> direct; // the same class ParaView runs, fed directly
  direct->SetInputData(0, cageData);
  direct->SetCageData(openCage);
  ErrorCounter openErrors;
  vtkNew<vtkCallbackCommand> observer;
  observer->SetCallback(&ErrorCounter::Count);
  observer->SetClientData(&openErrors);
  direct->AddObserver(vtkCommand::ErrorEvent, observer);
  direct->Update();
  check(openErrors.errors > 0, "an open cage is an error");
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc != 3 && argc != 4)
  {
    std::cerr << "usage: TestBaryLabParaViewPlugin <plugin .so> <data folder> [<output folder>]\n";
    return 2;
  }
  if (argc == 4)
    outputDir = argv[3];
  vtkInitializationHelper::SetLoadSettingsFilesDuringInitialization(false);
  if (!vtkInitializationHelper::Initialize(argv[0], vtkProcessModule::PROCESS_CLIENT))
  {
    std::cerr << "ParaView's initialisation failed\n";
    return 1;
  }
  std::cout.setf(std::ios::unitbuf); // every line out before a crash, if one comes
  vtkSMSession::ConnectToSelf();
  vtkSMProxyManager* proxyManager = vtkSMProxyManager::GetProxyManager();
  {
    // the session's time keeper, selection and animation proxies, as the client makes them
    vtkNew<vtkSMParaViewPipelineController> controller;
    controller->InitializeSession(proxyManager->GetActiveSession());
  }
  vtkSMSessionProxyManager* pxm = proxyManager->GetActiveSessionProxyManager();
  const bool loaded = proxyManager->GetPluginManager()->LoadLocalPlugin(argv[1]);
  check(loaded, std::string("the plugin loads: ") + argv[1]);
  if (loaded && pxm)
  {
    CheckPluginProxies(pxm);
    CheckDefaults(pxm);
    CheckReaderFactory(proxyManager, argv[2]);
    Pipeline pipeline(pxm);
    CheckSettingsTable(pipeline);
    CheckWeightsAndDeformation(pipeline, argv[2]);
    CheckMesherAndErrors(pipeline, argv[2]);
    CheckWeightedAverage(pipeline);
    CheckSplineEdit(pipeline, argv[2]);
    pxm->UnRegisterProxies();
  }
  vtkInitializationHelper::Finalize();
  std::cout << (failures ? "FAILED: " : "passed: ") << failures << " failure(s)\n";
  return failures == 0 && loaded ? 0 : 1;
}
