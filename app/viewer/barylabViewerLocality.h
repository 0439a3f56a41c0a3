#pragma once
/// @file barylabViewerLocality.h
/// The viewer's locality charts: P(t) and Q(k) of Zhang et al., "Local barycentric
/// coordinates" (2014), Eq. 19-21 and Fig. 14-15, for the shown method and the comparison
/// method, drawn with QtCharts from the statistics barylab::LocalityStatisticsJson computes
/// (vtkBaryLocalityStatistics). Display code only; exportable as CSV (the columns of
/// `barylab stats --locality --csv`) and PNG. The LocalityDock shows them for a Session.

#include <nlohmann/json.hpp>

#include <QDockWidget>
#include <QWidget>

#include <string>

namespace QtCharts
{
class QChartView;
}
class QLabel;

namespace barylab
{
namespace viewer
{

class LocalityPanel : public QWidget
{
  Q_OBJECT
public:
  explicit LocalityPanel(QWidget* parent = nullptr);

  /// @p statistics: an array of LocalityStatisticsJson objects, each with a "method" key, all
  /// of the same weights (same points, same number of controls) or of different methods on the
  /// same points. An empty array clears the charts.
  void setStatistics(const nlohmann::json& statistics);
  const nlohmann::json& statistics() const { return this->Statistics; }

  /// Writes PREFIX_P.csv (t, then P of each method) and PREFIX_Q.csv (k, then Q of each
  /// method). @throws bary::Error(Io) when a file cannot be written, InvalidArgument when there
  /// is nothing to write.
  void writeCsv(const std::string& prefix) const;
  /// Writes both charts, side by side, to a PNG. @throws bary::Error(Io).
  void writePng(const std::string& path);

  QtCharts::QChartView* pChart() const { return this->PView; }
  QtCharts::QChartView* qChart() const { return this->QView; }

private:
  nlohmann::json Statistics = nlohmann::json::array();
  QtCharts::QChartView* PView = nullptr;
  QtCharts::QChartView* QView = nullptr;
  QLabel* Summary = nullptr;
};

class Session;

/// The dock ("Locality statistics", bottom) holding the charts of a session's weights and
/// comparison weights; the statistics are recomputed whenever it becomes visible.
class LocalityDock : public QDockWidget
{
  Q_OBJECT
public:
  /// @p session must outlive the dock.
  LocalityDock(const Session& session, QWidget* parent);

  LocalityPanel* panel() const { return this->Panel; }
  /// Shows the dock (recomputing the statistics, also when it was visible already) or hides it.
  void setShown(bool on);
  /// Recomputes the statistics of the session's weights; on a failure the charts are cleared
  /// and failed() is emitted.
  void refresh();
  /// refresh(), then LocalityPanel::writeCsv. @throws bary::Error
  void writeCsv(const QString& prefix);
  /// refresh(), then LocalityPanel::writePng. @throws bary::Error(InvalidArgument) when there
  /// are no statistics (no weights), Error(Io)
  void writePng(const QString& path);

signals:
  void failed(const QString& message);

private:
  const Session& State;
  LocalityPanel* Panel = nullptr;
};

} // namespace viewer
} // namespace barylab
