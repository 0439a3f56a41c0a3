#include "barylabViewerExamples.h"

#include "barylabViewerSession.h"

namespace barylab
{
namespace viewer
{
QString DataPath(const char* name)
{
  return QString(BARYLAB_DEFAULT_DATA_DIR) + "/" + name;
}

Inputs Example::inputs() const
{
  Inputs in;
  in.controls = DataPath(this->controls);
  in.model = DataPath(this->model);
  if (*this->domain)
    in.domain = DataPath(this->domain);
  in.example = this->name;
  in.pose = DataPath(this->pose);
  return in;
}

const std::vector<Example>& Examples()
{
  static const std::vector<Example> examples = {
    { "gingerbread-mvc", "cage2d.obj", "model2d.obj", "", "mvc", "cage2d_posed.obj", 14 },
    { "kidney-mvc", "cage3d.obj", "model3d.off", "", "mvc", "cage3d_posed.obj", 36 },
    { "gingerbread-bbw", "skeleton2d.tgf", "model2d.obj", "cage2d.obj", "bbw",
      "skeleton2d_pose.txt", 3 },
    { "heart-scc", "heart_controls.obj", "heart.off", "", "scc", "heartbeat/frame_05.obj", 0 },
    // local barycentric coordinates: compare with mvc and open the locality charts (S)
    { "gingerbread-lbc", "cage2d.obj", "model2d.obj", "", "lbc", "cage2d_posed.obj", 14 },
    // 2D image mode: a picture as the model, warped as a texture by the cage
    { "gingerbread-image", "cage2d.obj", "gingerbread.png", "", "mvc", "cage2d_posed.obj", 14 },
  };
  return examples;
}

QStringList ExampleNames()
{
  QStringList names;
  for (const Example& e : Examples())
    names << e.name;
  return names;
}

const Example* FindExample(const QString& name)
{
  for (const Example& e : Examples())
    if (name == e.name)
      return &e;
  return nullptr;
}

} // namespace viewer
} // namespace barylab
