// SPDX-License-Identifier: MIT
/// @brief One questionnaire page of a study session (paper §IV-B): every item of the study's
///        questionnaires for one visual mode. Each answer is stored the moment it is given (one
///        transaction each), so a crash on a half-filled page loses nothing and a resumed page
///        shows what was answered; the page can be saved (finished) only when every item has an
///        answer. Items of at most eleven points are radio buttons (Likert 1–7, SUS 1–5), wider
///        scales a spin box (NASA-TLX 0–100) that starts unanswered.
#pragma once

#include <QWidget>
#include <map>
#include <string>
#include <vector>

#include "console/study/study_definition.h"

class QAbstractButton;
class QButtonGroup;
class QLabel;
class QPushButton;
class QSpinBox;

namespace telesphere::console {

namespace study {
class StudyStore;
}

class QuestionnairePage : public QWidget {
  Q_OBJECT

 public:
  /// `answered`: what the store already holds for this session and mode (item key → value).
  QuestionnairePage(study::StudyStore& store, std::int64_t session_id, const std::string& mode,
                    const QString& title, const std::vector<study::Questionnaire>& questionnaires,
                    const std::map<std::pair<std::string, std::string>, double>& answered, QWidget* parent = nullptr);

  const std::string& mode() const { return mode_; }
  int itemCount() const { return static_cast<int>(inputs_.size()); }
  int answeredCount() const;
  bool complete() const { return answeredCount() == itemCount(); }
  QPushButton* saveButton() const { return save_; }
  /// Answers item `item` of `instrument` through its widget, as a click would (tests).
  bool answer(const std::string& instrument, const std::string& item, int value);
  /// The last storage error (empty when every answer was stored).
  const QString& lastError() const { return error_; }

 signals:
  void saved();  ///< the administrator saved the complete page

 private:
  struct Input {
    std::string instrument, item;
    QButtonGroup* buttons = nullptr;  ///< radio buttons, id = value
    QSpinBox* spin = nullptr;         ///< min − 1 = unanswered
  };
  void storeAnswer(const Input& input, int value);
  void updateProgress();

  study::StudyStore& store_;
  std::int64_t session_id_;
  std::string mode_;
  std::vector<Input> inputs_;
  QLabel* progress_;
  QPushButton* save_;
  QString error_;
};

}  // namespace telesphere::console
