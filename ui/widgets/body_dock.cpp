#include "ui/widgets/body_dock.h"

#include "io/body_file.h"

#include "patterns/mannequin.h"

#include <QAction>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QLabel>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QToolButton>

#include <algorithm>
#include <cmath>

namespace atelier::ui {

namespace {

constexpr double CM = 100.0;

/// "under_bust" -> "Under bust".
QString label(std::string_view name) {
    QString text = QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size()));
    text.replace('_', ' ');
    text[0] = text[0].toUpper();
    return text;
}

} // namespace

BodyDock::BodyDock(QAction* importBody, QWidget* parent) : QDockWidget(tr("Body"), parent) {
    setObjectName("body-dock");
    auto* widget = new QWidget;
    auto* form = new QFormLayout(widget);
    m_base = new QComboBox;
    m_base->addItems({QStringLiteral("female"), QStringLiteral("male")});
    form->addRow(tr("Mannequin"), m_base);
    for (const auto& [name, member] : patterns::measurementFields()) {
        auto* box = new QDoubleSpinBox;
        box->setRange(1, 300);
        box->setDecimals(1);
        box->setSingleStep(1);
        box->setSuffix(tr(" cm"));
        box->setKeyboardTracking(false); // typed values count once finished
        const QString key = QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size()));
        form->addRow(label(name), box);
        m_fields.emplace_back(key, box);
        connect(box, &QDoubleSpinBox::valueChanged, this,
                [this, key](double value) { fieldChanged(key, value); });
    }
    m_problem = new QLabel;
    m_problem->setWordWrap(true);
    m_problem->setStyleSheet("color: #b03020");
    form->addRow(m_problem);
    m_mesh = new QLabel;
    m_mesh->setWordWrap(true);
    m_mesh->setTextInteractionFlags(Qt::TextSelectableByMouse);
    form->addRow(tr("Mesh"), m_mesh);
    m_import = new QToolButton;
    m_import->setDefaultAction(importBody);
    m_import->setToolButtonStyle(Qt::ToolButtonTextOnly);
    form->addRow(m_import);
    // Eleven fields are taller than a window's dock area may be: they scroll.
    auto* scroll = new QScrollArea;
    scroll->setWidget(widget);
    scroll->setWidgetResizable(true);
    scroll->setFrameShape(QFrame::NoFrame);
    setWidget(scroll);

    m_delay.setSingleShot(true);
    m_delay.setInterval(PREVIEW_DELAY_MS);
    connect(&m_delay, &QTimer::timeout, this, [this] {
        if (!(m_shown == m_body)) {
            Q_EMIT bodyEdited(m_shown, m_lastField);
        }
    });
    connect(m_base, &QComboBox::activated, this, [this] {
        m_shown.base = m_base->currentText().toStdString();
        m_shown.measurements.clear(); // the new base's own measurements
        m_lastField = QStringLiteral("base");
        m_delay.start();
    });
    refresh();
}

void BodyDock::setBody(const patterns::BodySource& body) {
    if (body == m_body) {
        return; // a document edit: a change being typed stays
    }
    m_body = body;
    m_shown = body;
    m_delay.stop();
    refresh();
}

QDoubleSpinBox* BodyDock::field(const QString& name) const {
    for (const auto& [key, box] : m_fields) {
        if (key == name) {
            return box;
        }
    }
    return nullptr;
}

QString BodyDock::meshText() const {
    return m_body.meshPath.empty() ? QString() : m_mesh->text();
}

void BodyDock::setProblem(const QString& problem) {
    m_problem->setText(problem);
    m_problem->setVisible(!problem.isEmpty());
}

QString BodyDock::problem() const {
    return m_problem->text();
}

void BodyDock::fieldChanged(const QString& name, double valueCm) {
    // Only the field changed becomes an override; the others keep the base's or the file's.
    const std::string key = name.toStdString();
    auto& overrides = m_shown.measurements;
    const auto at = std::find_if(overrides.begin(), overrides.end(),
                                 [&](const auto& entry) { return entry.first == key; });
    const double metres = valueCm / CM;
    if (at != overrides.end()) {
        at->second = metres;
    } else {
        overrides.emplace_back(key, metres);
    }
    m_lastField = name;
    m_delay.start(); // restarted by every change: announced once they stop
}

void BodyDock::refresh() {
    const bool mannequin = m_body.meshPath.empty();
    std::vector<QSignalBlocker> blockers;
    blockers.emplace_back(m_base);
    m_base->setCurrentText(QString::fromStdString(m_body.base));
    m_base->setEnabled(mannequin);
    auto measured = io::bodyMeasurements(m_body, "");
    for (const auto& [name, member] : patterns::measurementFields()) {
        QDoubleSpinBox* box =
            field(QString::fromUtf8(name.data(), static_cast<qsizetype>(name.size())));
        blockers.emplace_back(box);
        box->setEnabled(mannequin && measured.ok());
        if (measured.ok()) {
            box->setValue(measured.value().*member * CM);
        }
    }
    if (mannequin) {
        m_mesh->setText(tr("none: the parametric mannequin"));
        setProblem(measured.ok() ? QString() : QString::fromStdString(measured.error().toString()));
    } else {
        const auto orDetected = [this](const std::string& value) {
            return value.empty() ? tr("detected") : QString::fromStdString(value);
        };
        m_mesh->setText(tr("%1\nunit: %2, up axis: %3")
                            .arg(QFileInfo(QString::fromStdString(m_body.meshPath)).fileName(),
                                 orDetected(m_body.meshUnits), orDetected(m_body.meshUp)));
        m_mesh->setToolTip(QString::fromStdString(m_body.meshPath));
        setProblem({});
    }
}

} // namespace atelier::ui
