#include "barylabViewerLocality.h"

#include "barylabPipeline.h"
#include "barylabViewerSession.h"

#include "core/common/error.h"

#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QLegend>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QValueAxis>

#include <QApplication>
#include <QHBoxLayout>
#include <QLabel>
#include <QPainter>
#include <QPixmap>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

using namespace QtCharts;

namespace barylab
{
namespace viewer
{
namespace
{
QChartView* make_view(const QString& title, QWidget* parent)
{
  auto* chart = new QChart;
  chart->setTitle(title);
  chart->legend()->setAlignment(Qt::AlignBottom);
  chart->setAnimationOptions(QChart::NoAnimation);
  auto* view = new QChartView(chart, parent);
  view->setRenderHint(QPainter::Antialiasing);
  view->setMinimumSize(320, 220);
  return view;
}

/// Series colours: the shown method blue, the comparison orange (as the views' titles).
const QColor kColours[] = { QColor(31, 100, 180), QColor(230, 120, 20), QColor(40, 150, 60),
  QColor(180, 40, 40) };

std::string method_of(const nlohmann::json& s, std::size_t i)
{
  return s.value("method", "weights " + std::to_string(i));
}

std::string csv_number(double v)
{
  std::ostringstream out;
  out << std::setprecision(17) << v;
  return out.str();
}
/// Fills the P and Q charts (cleared first) with @p statistics; returns the summary lines.
QStringList fill_charts(QChart* p, QChart* q, const nlohmann::json& statistics)
{
  p->removeAllSeries();
  q->removeAllSeries();
  for (QChart* chart : { p, q })
    for (QAbstractAxis* axis : chart->axes())
    {
      chart->removeAxis(axis);
      delete axis;
    }
  auto* t_axis = new QLogValueAxis;
  t_axis->setBase(10.0);
  t_axis->setLabelFormat("%.0e");
  t_axis->setTitleText("t");
  t_axis->setRange(1e-6, 1.0);
  t_axis->setMinorTickCount(-1);
  auto* p_axis = new QValueAxis;
  p_axis->setRange(0.0, 1.0);
  p_axis->setTitleText("P(t)");
  p->addAxis(t_axis, Qt::AlignBottom);
  p->addAxis(p_axis, Qt::AlignLeft);
  auto* k_axis = new QValueAxis;
  k_axis->setTitleText("k");
  k_axis->setLabelFormat("%d");
  auto* q_axis = new QValueAxis;
  q_axis->setRange(0.0, 1.0);
  q_axis->setTitleText("Q(k)");
  q->addAxis(k_axis, Qt::AlignBottom);
  q->addAxis(q_axis, Qt::AlignLeft);

  int k_max = 1;
  QStringList lines;
  for (std::size_t i = 0; i < statistics.size(); ++i)
  {
    const nlohmann::json& s = statistics[i];
    const QString name = QString::fromStdString(method_of(s, i));
    const QColor colour = kColours[i % 4];
    auto* ps = new QLineSeries;
    ps->setName(name);
    ps->setColor(colour);
    const auto& t = s.at("t");
    const auto& P = s.at("P");
    for (std::size_t j = 0; j < t.size(); ++j)
      if (t[j].get<double>() > 0.0) // the log axis leaves t = 0 out
        ps->append(t[j].get<double>(), P[j].get<double>());
    p->addSeries(ps);
    ps->attachAxis(t_axis);
    ps->attachAxis(p_axis);
    auto* qs = new QLineSeries;
    qs->setName(name);
    qs->setColor(colour);
    qs->setPointsVisible(true);
    const auto& k = s.at("k");
    const auto& Q = s.at("Q");
    for (std::size_t j = 0; j < k.size(); ++j)
    {
      qs->append(k[j].get<double>(), Q[j].get<double>());
      k_max = std::max(k_max, k[j].get<int>());
    }
    q->addSeries(qs);
    qs->attachAxis(k_axis);
    qs->attachAxis(q_axis);
    lines << QString("<b>%1</b>: mean support %2, max %3 of %4 controls (threshold %5, %6 measure)")
               .arg(name)
               .arg(s.value("mean_support", 0.0), 0, 'f', 2)
               .arg(s.value("max_support", 0.0), 0, 'f', 0)
               .arg(k.size())
               .arg(s.value("threshold", 0.0), 0, 'g', 3)
               .arg(QString::fromStdString(s.value("measure", std::string("uniform"))));
  }
  k_axis->setRange(1.0, std::max(2, k_max));
  k_axis->setTickCount(std::min(k_max, 10) + 1 > 2 ? std::min(k_max, 10) + 1 : 2);
  return lines;
}

} // namespace

LocalityPanel::LocalityPanel(QWidget* parent)
  : QWidget(parent)
{
  auto* layout = new QVBoxLayout(this);
  auto* charts = new QHBoxLayout;
  this->PView = make_view("P(t): fraction of the domain where w<sub>i</sub> &le; t", this);
  this->QView = make_view("Q(k): fraction of the domain with &ge; k weights &gt; 10<sup>-3</sup>/n", this);
  this->PView->setObjectName("locality_P");
  this->QView->setObjectName("locality_Q");
  charts->addWidget(this->PView);
  charts->addWidget(this->QView);
  layout->addLayout(charts);
  this->Summary = new QLabel(this);
  this->Summary->setObjectName("locality_summary");
  this->Summary->setWordWrap(true);
  layout->addWidget(this->Summary);
  this->setStatistics(nlohmann::json::array());
}

void LocalityPanel::setStatistics(const nlohmann::json& statistics)
{
  this->Statistics = statistics.is_array() ? statistics : nlohmann::json::array();
  const QStringList lines = fill_charts(this->PView->chart(), this->QView->chart(), this->Statistics);
  this->Summary->setText(lines.isEmpty() ? QString("Compute weights to see their locality.")
                                         : lines.join("<br>"));
}

void LocalityPanel::writeCsv(const std::string& prefix) const
{
  if (this->Statistics.empty())
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "no locality statistics to export: compute weights first");
  const auto open = [](const std::string& path) {
    std::ofstream out(path);
    if (!out)
      throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
    return out;
  };
  {
    std::ofstream out = open(prefix + "_P.csv");
    out << "t";
    for (std::size_t i = 0; i < this->Statistics.size(); ++i)
      out << ",P_" << method_of(this->Statistics[i], i);
    out << "\n";
    const auto& t = this->Statistics[0].at("t");
    for (std::size_t j = 0; j < t.size(); ++j)
    {
      out << csv_number(t[j].get<double>());
      for (const auto& s : this->Statistics)
        out << "," << (j < s.at("P").size() ? csv_number(s.at("P")[j].get<double>()) : "");
      out << "\n";
    }
    if (!out)
      throw bary::Error(bary::ErrorCode::Io, "cannot write '" + prefix + "_P.csv'");
  }
  {
    std::ofstream out = open(prefix + "_Q.csv");
    out << "k";
    std::size_t rows = 0;
    for (std::size_t i = 0; i < this->Statistics.size(); ++i)
    {
      out << ",Q_" << method_of(this->Statistics[i], i);
      rows = std::max(rows, this->Statistics[i].at("k").size());
    }
    out << "\n";
    for (std::size_t j = 0; j < rows; ++j)
    {
      out << j + 1;
      for (const auto& s : this->Statistics)
        out << "," << (j < s.at("Q").size() ? csv_number(s.at("Q")[j].get<double>()) : "");
      out << "\n";
    }
    if (!out)
      throw bary::Error(bary::ErrorCode::Io, "cannot write '" + prefix + "_Q.csv'");
  }
}

void LocalityPanel::writePng(const std::string& path)
{
  // fresh charts in views that are laid out but never shown on screen, so the PNG has the
  // same fixed size and layout whatever the panel's size in the window
  const QSize half(500, 420);
  QChartView* views[2] = { make_view(this->PView->chart()->title(), nullptr),
    make_view(this->QView->chart()->title(), nullptr) };
  fill_charts(views[0]->chart(), views[1]->chart(), this->Statistics);
  QPixmap pixmap(half.width() * 2, half.height());
  pixmap.fill(Qt::white);
  QPainter painter(&pixmap);
  for (int i = 0; i < 2; ++i)
  {
    views[i]->setAttribute(Qt::WA_DontShowOnScreen);
    views[i]->resize(half);
    views[i]->show();
    QApplication::processEvents();
    painter.drawPixmap(i * half.width(), 0, views[i]->grab());
    delete views[i];
  }
  painter.end();
  if (!pixmap.save(QString::fromStdString(path), "PNG"))
    throw bary::Error(bary::ErrorCode::Io, "cannot write '" + path + "'");
}

LocalityDock::LocalityDock(const Session& session, QWidget* parent)
  : QDockWidget("Locality statistics", parent)
  , State(session)
  , Panel(new LocalityPanel(this))
{
  this->setObjectName("locality_dock");
  this->setWidget(this->Panel);
  connect(this, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    if (visible)
      this->refresh();
  });
}

void LocalityDock::setShown(bool on)
{
  if (on)
  {
    this->show();
    this->refresh(); // also when it was visible already
  }
  else
    this->hide();
}

void LocalityDock::refresh()
{
  nlohmann::json all = nlohmann::json::array();
  try
  {
    const std::pair<vtkDataSet*, std::string> shown[] = {
      { this->State.weighted(), MethodName(this->State.computed()) },
      { this->State.compareWeighted(), this->State.computedCompare().toStdString() } };
    for (const auto& [data, method] : shown)
      if (data)
      {
        nlohmann::json s = LocalityStatisticsJson(data, this->State.computed().weights_name);
        s["method"] = method;
        all.push_back(std::move(s));
      }
  }
  catch (const std::exception& e)
  {
    emit failed(QString("locality statistics: ") + e.what());
    all = nlohmann::json::array();
  }
  this->Panel->setStatistics(all);
}

void LocalityDock::writeCsv(const QString& prefix)
{
  this->refresh();
  this->Panel->writeCsv(prefix.toStdString());
}

void LocalityDock::writePng(const QString& path)
{
  this->refresh();
  if (this->Panel->statistics().empty())
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      "no locality statistics to export: compute weights first");
  this->Panel->writePng(path.toStdString());
}

} // namespace viewer
} // namespace barylab
