#pragma once
/// @file barylabViewerPanel.h
/// The viewer's side panel: inputs, method and its parameter rows (generated from
/// WeightsParameterFields), controls list, display options, deformation row and statistics.
/// Every widget calls the window's public slots, as a person would through the menus; sync()
/// puts the window's state back into the widgets without feedback.

#include <nlohmann/json.hpp>

#include <QScrollArea>
#include <QStringList>

#include <utility>
#include <vector>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPushButton;
class QSlider;
class QSpinBox;
class QVBoxLayout;

namespace barylab
{
namespace viewer
{
class Session;
class ViewerWindow;

class ControlPanel : public QScrollArea
{
  Q_OBJECT
public:
  /// The panel of @p window, connected to its slots (with every mode's panel widgets).
  explicit ControlPanel(ViewerWindow* window);

  /// Widgets from the window's state (parameters, display options, busy), without feedback.
  void sync();
  /// @p session's inputs just opened: the Inputs group's text (files and their points) and
  /// the range of the Move row's id (one per control).
  void setInputs(const Session& session);
  /// The Controls list (one label per weights component), @p current selected.
  void setControlLabels(const QStringList& labels, int current);
  /// The selected control's label ("" when none).
  QString currentControlLabel() const;
  /// The Move row's id (its position follows from the posed controls).
  void setMoveId(int id);
  /// The Move row's position.
  void setMovePosition(const double p[3]);
  /// The statistics line under the panel: @p method's weights computed in @p seconds, their
  /// size, range, partition of unity error and locality (@p statistics: WeightStatisticsJson).
  void setStatistics(const QString& method, double seconds, const nlohmann::json& statistics);

private:
  void buildParameterRows(QVBoxLayout* form);

  ViewerWindow* Window;
  bool Updating = false; ///< widgets being synchronised from the state: ignore their signals
  QLabel* InputsLabel = nullptr;
  QComboBox* MethodBox = nullptr;
  QComboBox* CompareBox = nullptr;
  std::vector<std::pair<QWidget*, QWidget*>> ParameterWidgets; ///< (row, editor) per table row
  QPushButton* ComputeButton = nullptr;
  QPushButton* CancelButton = nullptr;
  QListWidget* ControlList = nullptr;
  QComboBox* FieldBox = nullptr;
  QCheckBox* LogBox = nullptr;
  QSpinBox* IsolineBox = nullptr;
  QCheckBox* InfluenceBox = nullptr;
  QCheckBox* ClipBox = nullptr;
  QComboBox* ClipAxisBox = nullptr;
  QSlider* ClipSlider = nullptr;
  QSpinBox* MoveIdBox = nullptr;
  QDoubleSpinBox* MoveBox[3] = { nullptr, nullptr, nullptr };
  QLabel* StatsLabel = nullptr;
};

} // namespace viewer
} // namespace barylab
