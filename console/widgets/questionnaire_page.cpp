// SPDX-License-Identifier: MIT
/// @brief QuestionnairePage (see questionnaire_page.h).
#include "console/widgets/questionnaire_page.h"

#include <QButtonGroup>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QRadioButton>
#include <QScrollArea>
#include <QSpinBox>
#include <QVBoxLayout>

#include "console/study/study_store.h"

namespace telesphere::console {

QuestionnairePage::QuestionnairePage(study::StudyStore& study_store, std::int64_t session_id, const std::string& mode,
                                     const QString& title, const std::vector<study::Questionnaire>& questionnaires,
                                     const std::map<std::pair<std::string, std::string>, double>& answered,
                                     QWidget* parent)
    : QWidget(parent), store_(study_store), session_id_(session_id), mode_(mode) {
  auto* outer = new QVBoxLayout(this);
  auto* heading = new QLabel("<b>" + title + "</b>");
  heading->setObjectName("questionnaireTitle");
  outer->addWidget(heading);
  auto* scroll = new QScrollArea;
  scroll->setWidgetResizable(true);
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  for (const study::Questionnaire& q : questionnaires) {
    const QString name = q.instrument == "paper_likert"   ? "The paper's questions (Likert 1–7)"
                         : q.instrument == "nasa_tlx_raw" ? "NASA-TLX, raw (0–100)"
                         : q.instrument == "sus"          ? "System Usability Scale (1: strongly disagree … 5: strongly agree)"
                                                          : QString::fromStdString(q.instrument);
    auto* box = new QGroupBox(name);
    auto* grid = new QGridLayout(box);
    int row = 0;
    for (const study::QuestionnaireItem& item : q.items) {
      auto* text = new QLabel(QString::fromStdString(item.text));
      text->setWordWrap(true);
      grid->addWidget(text, row, 0);
      Input input{q.instrument, item.key};
      const auto given = answered.find({q.instrument, item.key});
      auto* choices = new QWidget;
      auto* row_layout = new QHBoxLayout(choices);
      row_layout->setContentsMargins(0, 0, 0, 0);
      if (item.max - item.min <= 10) {
        input.buttons = new QButtonGroup(this);
        row_layout->addWidget(new QLabel(QString::number(item.min)));
        for (int v = item.min; v <= item.max; ++v) {
          auto* b = new QRadioButton;
          b->setToolTip(QString::number(v));
          b->setObjectName(QString::fromStdString(q.instrument + "." + item.key + "." + std::to_string(v)));
          input.buttons->addButton(b, v);
          row_layout->addWidget(b);
          if (given != answered.end() && int(given->second) == v) b->setChecked(true);
        }
        row_layout->addWidget(new QLabel(QString::number(item.max)));
      } else {
        input.spin = new QSpinBox;
        input.spin->setRange(item.min - 1, item.max);
        input.spin->setSpecialValueText("not answered");
        input.spin->setValue(given != answered.end() ? int(given->second) : item.min - 1);
        input.spin->setObjectName(QString::fromStdString(q.instrument + "." + item.key));
        row_layout->addWidget(input.spin);
      }
      grid->addWidget(choices, row, 1);
      grid->setColumnStretch(0, 1);
      const std::size_t index = inputs_.size();
      inputs_.push_back(input);
      if (input.buttons)
        connect(input.buttons, &QButtonGroup::idClicked, this, [this, index](int v) { storeAnswer(inputs_[index], v); });
      else
        connect(input.spin, &QSpinBox::valueChanged, this, [this, index](int v) {
          if (v >= inputs_[index].spin->minimum() + 1) storeAnswer(inputs_[index], v);
        });
      ++row;
    }
    layout->addWidget(box);
  }
  layout->addStretch(1);
  scroll->setWidget(body);
  outer->addWidget(scroll, 1);
  auto* bottom = new QHBoxLayout;
  progress_ = new QLabel;
  progress_->setObjectName("questionnaireProgress");
  bottom->addWidget(progress_, 1);
  save_ = new QPushButton("Save page");
  save_->setObjectName("saveQuestionnairePage");
  connect(save_, &QPushButton::clicked, this, [this] {
    if (complete()) emit saved();
  });
  bottom->addWidget(save_);
  outer->addLayout(bottom);
  updateProgress();
}

int QuestionnairePage::answeredCount() const {
  int n = 0;
  for (const Input& in : inputs_)
    n += in.buttons ? in.buttons->checkedId() != -1 : in.spin->value() > in.spin->minimum();
  return n;
}

void QuestionnairePage::storeAnswer(const Input& input, int value) {
  std::string why;
  if (!store_.saveAnswer(session_id_, mode_, input.instrument, input.item, value, &why))
    error_ = "answer not stored: " + QString::fromStdString(why);
  else
    error_.clear();
  updateProgress();
}

void QuestionnairePage::updateProgress() {
  const int n = answeredCount();
  QString text = QString("%1 of %2 answered (each answer is stored as it is given)").arg(n).arg(itemCount());
  if (!complete()) text += " — the page can be saved when every item has an answer";
  if (!error_.isEmpty()) text = "<b style='color:#b3261e'>" + error_.toHtmlEscaped() + "</b>";
  progress_->setText(text);
  save_->setEnabled(complete() && error_.isEmpty());
}

bool QuestionnairePage::answer(const std::string& instrument, const std::string& item, int value) {
  for (Input& in : inputs_) {
    if (in.instrument != instrument || in.item != item) continue;
    if (in.buttons) {
      QAbstractButton* b = in.buttons->button(value);
      if (!b) return false;
      b->click();
    } else {
      in.spin->setValue(value);
    }
    return true;
  }
  return false;
}

}  // namespace telesphere::console
