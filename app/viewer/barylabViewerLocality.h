#pragma once
/// @file barylabViewerLocality.h
/// The viewer's locality charts: P(t) and Q(k) of Zhang et al., "Local barycentric
/// coordinates" (2014), Eq. 19-21 and Fig. 14-15, for the shown method and the comparison
/// method, drawn with QtCharts from the statistics barylab::LocalityStatisticsJson computes
/// (vtkBaryLocalityStatistics). Display code only; exportable as CSV (the columns of
/// `barylab stats --locality --csv`) and PNG.

#include <nlohmann/json.hpp>

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

} // namespace viewer
} // namespace barylab
