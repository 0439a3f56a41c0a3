#include "barylabViewerPanel.h"

#include "barylabViewerMode.h"
#include "barylabViewerParameters.h"
#include "barylabViewerWindow.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QDoubleValidator>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QPushButton>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>

#include "vtkDataSet.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace barylab
{
namespace viewer
{

ControlPanel::ControlPanel(ViewerWindow* window)
  : Window(window)
{
  auto* panel = new QWidget;
  auto* layout = new QVBoxLayout(panel);

  auto* inputs = new QGroupBox("Inputs");
  auto* inputsLayout = new QVBoxLayout(inputs);
  this->InputsLabel = new QLabel("(none)");
  this->InputsLabel->setMinimumHeight(3 * this->fontMetrics().height() + 6);
  this->InputsLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);
  inputsLayout->addWidget(this->InputsLabel);
  layout->addWidget(inputs);

  auto* method = new QGroupBox("Method");
  auto* methodLayout = new QVBoxLayout(method);
  auto* form = new QFormLayout;
  this->MethodBox = new QComboBox;
  this->CompareBox = new QComboBox;
  this->CompareBox->addItem("(none)", QString());
  for (const std::string& name : MethodNames())
  {
    this->MethodBox->addItem(QString::fromStdString(name), QString::fromStdString(name));
    this->CompareBox->addItem(QString::fromStdString(name), QString::fromStdString(name));
  }
  this->MethodBox->setObjectName("method");
  this->CompareBox->setObjectName("compare");
  this->CompareBox->setToolTip("a second method shown side by side, cameras linked");
  form->addRow("Method", this->MethodBox);
  form->addRow("Compare with", this->CompareBox);
  methodLayout->addLayout(form);
  auto* parameterForm = new QVBoxLayout; // one row widget per table row: hidden rows leave no gap
  parameterForm->setContentsMargins(0, 0, 0, 0);
  methodLayout->addLayout(parameterForm);
  this->buildParameterRows(parameterForm);
  auto* buttons = new QHBoxLayout;
  this->ComputeButton = new QPushButton("Compute");
  this->ComputeButton->setObjectName("compute");
  this->CancelButton = new QPushButton("Cancel");
  this->CancelButton->setObjectName("cancel");
  this->CancelButton->setEnabled(false);
  buttons->addWidget(this->ComputeButton);
  buttons->addWidget(this->CancelButton);
  methodLayout->addLayout(buttons);
  layout->addWidget(method);
  connect(this->MethodBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Updating)
      this->Window->setMethod(this->MethodBox->currentData().toString());
  });
  connect(this->CompareBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int) {
    if (!this->Updating)
      this->Window->setCompareMethod(this->CompareBox->currentData().toString());
  });
  connect(this->ComputeButton, &QPushButton::clicked, window, &ViewerWindow::compute);
  connect(this->CancelButton, &QPushButton::clicked, window, &ViewerWindow::cancel);

  auto* controls = new QGroupBox("Controls (weight shown)");
  auto* controlsLayout = new QVBoxLayout(controls);
  this->ControlList = new QListWidget;
  this->ControlList->setObjectName("controls");
  this->ControlList->setMinimumHeight(110);
  controlsLayout->addWidget(this->ControlList);
  layout->addWidget(controls);
  connect(this->ControlList, &QListWidget::currentRowChanged, this, [this](int row) {
    if (!this->Updating && row >= 0)
      this->Window->selectControl(row);
  });

  auto* display = new QGroupBox("Display");
  auto* displayForm = new QFormLayout(display);
  this->FieldBox = new QComboBox;
  this->FieldBox->addItems({ "weight", "gradient norm", "image" });
  this->LogBox = new QCheckBox("logarithmic colour scale");
  this->IsolineBox = new QSpinBox;
  this->IsolineBox->setRange(0, 50);
  this->InfluenceBox = new QCheckBox("influence level 10^-3/n");
  this->ClipBox = new QCheckBox("clip (3D)");
  this->ClipAxisBox = new QComboBox;
  this->ClipAxisBox->addItems({ "x", "y", "z" });
  this->ClipSlider = new QSlider(Qt::Horizontal);
  this->ClipSlider->setRange(0, 100);
  displayForm->addRow("Field", this->FieldBox);
  displayForm->addRow(this->LogBox);
  displayForm->addRow("Level sets", this->IsolineBox);
  displayForm->addRow(this->InfluenceBox);
  auto* clipRow = new QHBoxLayout;
  clipRow->addWidget(this->ClipBox);
  clipRow->addWidget(this->ClipAxisBox);
  displayForm->addRow(clipRow);
  displayForm->addRow("Clip position", this->ClipSlider);
  layout->addWidget(display);
  connect(this->FieldBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int i) {
    if (!this->Updating)
      i == 0 ? this->Window->showWeight()
             : i == 1 ? this->Window->showGradientNorm() : this->Window->showImage();
  });
  connect(this->LogBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
      this->Window->setLogScale(on);
  });
  connect(this->IsolineBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int n) {
    if (!this->Updating)
      this->Window->setIsolines(n);
  });
  connect(this->InfluenceBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
      this->Window->setInfluenceLevel(on);
  });
  connect(this->ClipBox, &QCheckBox::toggled, this, [this](bool on) {
    if (!this->Updating)
      this->Window->setClipping(on);
  });
  connect(this->ClipAxisBox, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this](int a) {
    if (!this->Updating)
      this->Window->setClipAxis(a);
  });
  connect(this->ClipSlider, &QSlider::valueChanged, this, [this](int v) {
    if (!this->Updating)
      this->Window->setClipPosition(v / 100.0);
  });

  auto* deform = new QGroupBox("Deformation");
  auto* deformLayout = new QVBoxLayout(deform);
  auto* moveRow = new QHBoxLayout;
  this->MoveIdBox = new QSpinBox;
  this->MoveIdBox->setPrefix("#");
  moveRow->addWidget(this->MoveIdBox);
  for (auto*& box : this->MoveBox)
  {
    box = new QDoubleSpinBox;
    box->setRange(-1e6, 1e6);
    box->setDecimals(4);
    box->setSingleStep(0.05);
    moveRow->addWidget(box);
  }
  deformLayout->addLayout(moveRow);
  auto* deformButtons = new QHBoxLayout;
  auto* setButton = new QPushButton("Move");
  auto* resetButton = new QPushButton("Reset");
  auto* undoButton = new QPushButton("Undo");
  deformButtons->addWidget(setButton);
  deformButtons->addWidget(resetButton);
  deformButtons->addWidget(undoButton);
  deformLayout->addLayout(deformButtons);
  for (const Mode* mode : Modes())
    mode->addPanelWidgets(deformLayout, *window);
  layout->addWidget(deform);
  connect(this->MoveIdBox, QOverload<int>::of(&QSpinBox::valueChanged), this, [this](int id) {
    vtkPoints* posed = this->Window->posedControls();
    if (posed && id >= 0 && id < posed->GetNumberOfPoints())
      this->setMovePosition(posed->GetPoint(id));
  });
  connect(setButton, &QPushButton::clicked, this, [this]() {
    this->Window->setControlPosition(this->MoveIdBox->value(), this->MoveBox[0]->value(),
      this->MoveBox[1]->value(), this->MoveBox[2]->value());
  });
  connect(resetButton, &QPushButton::clicked, window, &ViewerWindow::resetPose);
  connect(undoButton, &QPushButton::clicked, window, &ViewerWindow::undo);

  this->StatsLabel = new QLabel;
  this->StatsLabel->setWordWrap(true);
  layout->addWidget(this->StatsLabel);
  layout->addStretch(1);

  this->setWidget(panel);
  this->setWidgetResizable(true);
  this->setMinimumWidth(370);
  this->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
}

void ControlPanel::buildParameterRows(QVBoxLayout* form)
{
  for (const ParameterField& f : WeightsParameterFields())
  {
    QWidget* editor = nullptr;
    const QString key = QString::fromStdString(f.key);
    switch (f.kind)
    {
      case ParameterField::Kind::Bool:
      {
        auto* box = new QCheckBox;
        connect(box, &QCheckBox::toggled, this, [this, key](bool on) {
          if (!this->Updating)
            this->Window->setParameter(key, on);
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::Int:
      {
        auto* box = new QSpinBox;
        box->setRange(static_cast<int>(f.minimum), static_cast<int>(std::min(f.maximum, 2e9)));
        connect(box, QOverload<int>::of(&QSpinBox::valueChanged), this, [this, key](int v) {
          if (!this->Updating)
            this->Window->setParameter(key, v);
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::Double:
      {
        auto* box = new QLineEdit; // free-form: tolerances span many decades
        box->setValidator(new QDoubleValidator(f.minimum, f.maximum, 17, box));
        connect(box, &QLineEdit::editingFinished, this, [this, key, box]() {
          if (!this->Updating)
            this->Window->setParameter(key, box->text().toDouble());
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::Choice:
      {
        auto* box = new QComboBox;
        for (const std::string& c : f.choices)
          box->addItem(QString::fromStdString(c));
        connect(box, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this, key, box](int) {
          if (!this->Updating)
            this->Window->setParameter(key, box->currentText());
        });
        editor = box;
        break;
      }
      case ParameterField::Kind::String:
      {
        auto* box = new QLineEdit;
        connect(box, &QLineEdit::editingFinished, this, [this, key, box]() {
          if (!this->Updating)
            this->Window->setParameter(key, box->text());
        });
        editor = box;
        break;
      }
    }
    editor->setObjectName(key);
    editor->setToolTip(QString::fromStdString(f.tooltip));
    auto* row = new QWidget;
    auto* rowLayout = new QHBoxLayout(row);
    rowLayout->setContentsMargins(0, 0, 0, 0);
    auto* label = new QLabel(QString::fromStdString(f.label));
    label->setToolTip(editor->toolTip());
    label->setMinimumWidth(130);
    rowLayout->addWidget(label);
    rowLayout->addWidget(editor, 1);
    form->addWidget(row);
    this->ParameterWidgets.emplace_back(row, editor);
  }
}

void ControlPanel::sync()
{
  this->Updating = true;
  const WeightsParameters& parameters = this->Window->parameters();
  const QString compare = this->Window->compareMethod();
  const SceneOptions& options = this->Window->sceneOptions();
  this->MethodBox->setCurrentIndex(
    this->MethodBox->findData(QString::fromStdString(MethodName(parameters))));
  this->CompareBox->setCurrentIndex(std::max(0, this->CompareBox->findData(compare)));
  const auto& fields = WeightsParameterFields();
  for (std::size_t i = 0; i < fields.size(); ++i)
  {
    const ParameterField& f = fields[i];
    const nlohmann::json value = f.get(parameters);
    QWidget* editor = this->ParameterWidgets[i].second;
    const bool applies = f.AppliesTo(MethodName(parameters)) ||
      (!compare.isEmpty() && f.AppliesTo(compare.toStdString()));
    this->ParameterWidgets[i].first->setVisible(applies);
    if (auto* b = qobject_cast<QCheckBox*>(editor))
      b->setChecked(value.get<bool>());
    else if (auto* s = qobject_cast<QSpinBox*>(editor))
      s->setValue(value.get<int>());
    else if (auto* c = qobject_cast<QComboBox*>(editor))
      c->setCurrentText(value.is_string() ? QString::fromStdString(value.get<std::string>())
                                          : QString::fromStdString(value.dump()));
    else if (auto* l = qobject_cast<QLineEdit*>(editor))
      l->setText(value.is_string() ? QString::fromStdString(value.get<std::string>())
                                   : QString::number(value.get<double>(), 'g', 17));
  }
  this->FieldBox->setCurrentIndex(options.field == SceneOptions::Field::Weight ? 0
      : options.field == SceneOptions::Field::GradientNorm                  ? 1
                                                                            : 2);
  this->LogBox->setChecked(options.log_scale);
  this->IsolineBox->setValue(options.isolines);
  this->InfluenceBox->setChecked(options.influence_level);
  this->ClipBox->setChecked(options.clip);
  this->ClipAxisBox->setCurrentIndex(options.clip_axis);
  this->ClipSlider->setValue(static_cast<int>(std::lround(options.clip_position * 100.0)));
  this->ComputeButton->setEnabled(!this->Window->isComputing());
  this->CancelButton->setEnabled(this->Window->isComputing());
  if (this->ControlList->currentRow() != options.component &&
    options.component < this->ControlList->count())
    this->ControlList->setCurrentRow(options.component);
  this->Updating = false;
}

void ControlPanel::setInputs(const Session& session)
{
  const Inputs& in = session.inputs();
  const vtkIdType controls = session.controls()->GetNumberOfPoints();
  QString text = "<b>controls</b> " + QFileInfo(in.controls).fileName() + " (" +
    QString::number(controls) + " points)<br><b>model</b> " + QFileInfo(in.model).fileName() +
    " (" + QString::number(session.model()->GetNumberOfPoints()) + " points)";
  if (!in.domain.isEmpty())
    text += "<br><b>domain</b> " + QFileInfo(in.domain).fileName();
  this->InputsLabel->setText(text);
  this->MoveIdBox->setRange(0, std::max(0, static_cast<int>(controls) - 1));
}

void ControlPanel::setControlLabels(const QStringList& labels, int current)
{
  this->Updating = true;
  this->ControlList->clear();
  this->ControlList->addItems(labels);
  if (current < this->ControlList->count())
    this->ControlList->setCurrentRow(current);
  this->Updating = false;
}

QString ControlPanel::currentControlLabel() const
{
  return this->ControlList->currentItem() ? this->ControlList->currentItem()->text() : QString();
}

void ControlPanel::setMoveId(int id)
{
  this->MoveIdBox->setValue(id);
}

void ControlPanel::setMovePosition(const double p[3])
{
  for (int k = 0; k < 3; ++k)
    this->MoveBox[k]->setValue(p[k]);
}

void ControlPanel::setStatistics(const QString& method, double seconds,
  const nlohmann::json& statistics)
{
  const nlohmann::json& s = statistics;
  this->StatsLabel->setText(QString("%1 weights in %2 s: %3 points x %4 controls<br>"
                                    "min %5, max %6, partition of unity error %7<br>"
                                    "mean significant weights per point %8")
                              .arg(method)
                              .arg(seconds, 0, 'f', 3)
                              .arg(s.value("points", 0LL))
                              .arg(s.value("controls", 0LL))
                              .arg(s.value("min_weight", 0.0), 0, 'g', 3)
                              .arg(s.value("max_weight", 0.0), 0, 'g', 3)
                              .arg(s["partition_of_unity"].value("max_error", 0.0), 0, 'g', 2)
                              .arg(s["significant"].value("mean_per_point", 0.0), 0, 'g', 3));
}

} // namespace viewer
} // namespace barylab
