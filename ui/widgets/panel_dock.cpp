#include "ui/widgets/panel_dock.h"

#include "patterns/document_edit.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QScrollArea>
#include <QSignalBlocker>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

namespace atelier::ui {

namespace {

QDoubleSpinBox* spinBox(double min, double max, int decimals, const QString& suffix) {
    auto* box = new QDoubleSpinBox;
    box->setRange(min, max);
    box->setDecimals(decimals);
    box->setSuffix(suffix);
    box->setKeyboardTracking(false); // one value when typing ends, not one per key
    return box;
}

constexpr double MM = 1000.0;
constexpr double DEG = 180.0 / std::numbers::pi;

} // namespace

PanelDock::PanelDock(QWidget* parent) : QDockWidget(tr("Panel"), parent) {
    setObjectName("panel-dock");
    auto* body = new QWidget;
    auto* form = new QFormLayout(body);
    m_title = new QLabel;
    m_name = new QLineEdit;
    m_slot = new QComboBox;
    m_around = spinBox(-2000, 2000, 1, tr(" mm"));
    m_along = spinBox(-2000, 2000, 1, tr(" mm"));
    m_rotation = spinBox(-360, 360, 1, tr("°"));
    m_clearance = spinBox(0, 500, 1, tr(" mm"));
    m_fabric = new QComboBox;
    // 0 is the drape's distance; otherwise 1–1000 mm (patterns::MAX_PANEL_PARTICLE_DISTANCE).
    m_particleDistance = spinBox(0, 1000, 1, tr(" mm"));
    m_particleDistance->setSpecialValueText(tr("drape's"));
    m_particleDistance->setToolTip(
        tr("Mesh this panel finer or coarser than the rest (0: the drape's particle distance); "
           "a seam to another panel is sewn at the finer of the two"));
    // A fold's rest angle: 0 flat, ± towards either side, (−180°, 180°) exclusive.
    m_foldAngle = spinBox(-179.9, 179.9, 1, tr("°"));
    m_foldAngle->setToolTip(tr("The rest angle of the cloth's fold along the internal line "
                               "selected in the pattern (0: flat; select a line to edit)"));
    form->addRow(m_title);
    form->addRow(tr("Name"), m_name);
    form->addRow(tr("Slot"), m_slot);
    form->addRow(tr("Offset around"), m_around);
    form->addRow(tr("Offset along"), m_along);
    form->addRow(tr("Rotation"), m_rotation);
    form->addRow(tr("Clearance"), m_clearance);
    form->addRow(tr("Fabric"), m_fabric);
    form->addRow(tr("Particle distance"), m_particleDistance);
    form->addRow(tr("Fold angle"), m_foldAngle);
    // The dart whose leg is the edge selected in the pattern (patterns::setDartSize).
    m_dartWidth = spinBox(0, 2000, 1, tr(" mm"));
    m_dartDepth = spinBox(0, 2000, 1, tr(" mm"));
    m_dartWidth->setToolTip(tr("The width of the dart selected in the pattern (click one of its "
                               "legs): the distance between its legs' bases"));
    m_dartDepth->setToolTip(tr("The depth of the dart selected in the pattern: from the middle "
                               "between its legs' bases to its tip"));
    form->addRow(tr("Dart width"), m_dartWidth);
    form->addRow(tr("Dart depth"), m_dartDepth);
    // In a scroll area: the dock's rows (the dart's among them) never set the window's
    // smallest height.
    auto* scroll = new QScrollArea;
    scroll->setWidgetResizable(true);
    scroll->setFrameShape(QFrame::NoFrame);
    scroll->setWidget(body);
    setWidget(scroll);

    connect(m_name, &QLineEdit::editingFinished, this, [this] {
        const patterns::doc::Panel* p = shown();
        if (p != nullptr && m_name->text().toStdString() != p->name) {
            Q_EMIT renameRequested(m_panel.value, m_name->text());
        }
    });
    connect(m_slot, &QComboBox::activated, this, [this] { emitPlacement({}); });
    const std::pair<QDoubleSpinBox*, QString> fields[] = {
        {m_around, QStringLiteral("around")},
        {m_along, QStringLiteral("along")},
        {m_rotation, QStringLiteral("rotation")},
        {m_clearance, QStringLiteral("clearance")}};
    for (const auto& [box, field] : fields) {
        connect(box, &QDoubleSpinBox::valueChanged, this,
                [this, field = field] { emitPlacement(field); });
    }
    connect(m_particleDistance, &QDoubleSpinBox::valueChanged, this, [this](double mm) {
        const patterns::doc::Panel* p = shown();
        // Between 0 and 1 mm the value snaps to the drape's (0): below 1 mm is refused.
        const double metres = mm < 1 ? 0.0 : mm / MM;
        if (p != nullptr && metres != p->particleDistance) {
            Q_EMIT particleDistanceRequested(m_panel.value, metres);
        }
    });
    connect(m_foldAngle, &QDoubleSpinBox::valueChanged, this, [this](double degrees) {
        const patterns::doc::InternalLine* line = shownLine();
        // The field rounds to 0.1°: an angle the user left alone keeps its exact value.
        if (line != nullptr && std::abs(degrees - line->foldAngle * DEG) >= 0.05) {
            Q_EMIT foldAngleRequested(m_panel.value, m_line.value, degrees / DEG);
        }
    });
    for (QDoubleSpinBox* box : {m_dartWidth, m_dartDepth}) {
        connect(box, &QDoubleSpinBox::valueChanged, this, [this, box] {
            const patterns::doc::Panel* p = shown();
            const auto size = p == nullptr ? std::nullopt : patterns::dartSize(*p, m_dart);
            if (!size) {
                return;
            }
            // The fields round to 0.1 mm: a value the user left alone keeps its exact value.
            const double width = std::abs(m_dartWidth->value() - size->width * MM) >= 0.05
                                     ? m_dartWidth->value() / MM
                                     : size->width;
            const double depth = std::abs(m_dartDepth->value() - size->depth * MM) >= 0.05
                                     ? m_dartDepth->value() / MM
                                     : size->depth;
            if (width != size->width || depth != size->depth) {
                Q_EMIT dartSizeRequested(m_panel.value, m_dart.value, width, depth,
                                         box == m_dartWidth ? QStringLiteral("width")
                                                            : QStringLiteral("depth"));
            }
        });
    }
    connect(m_fabric, &QComboBox::activated, this, [this](int index) {
        const patterns::doc::Panel* p = shown();
        if (p == nullptr || index < 0) {
            return;
        }
        const QString name = m_fabric->itemData(index).toString();
        const bool preset = m_fabric->itemData(index, Qt::UserRole + 1).toBool();
        if (preset || name.toStdString() != p->material) {
            Q_EMIT fabricRequested(m_panel.value, name, preset);
        }
    });
    refresh();
}

void PanelDock::setDocument(const patterns::GarmentDocument& document) {
    m_document = document;
    if (m_document.panel(m_panel) == nullptr) {
        m_panel = {};
    }
    refresh();
}

void PanelDock::setSlotNames(const QStringList& names) {
    m_slotNames = names;
    refresh();
}

void PanelDock::setPresetNames(const QStringList& names) {
    m_presetNames = names;
    refresh();
}

void PanelDock::showPanel(quint32 panel) {
    if (panel != m_panel.value) {
        m_line = {};
        m_dart = {};
    }
    m_panel = patterns::PanelId{panel};
    if (m_document.panel(m_panel) == nullptr) {
        m_panel = {};
    }
    refresh();
}

void PanelDock::showLine(quint32 panel, quint32 line) {
    if (line != 0 && panel != m_panel.value) {
        showPanel(panel);
    }
    m_line = patterns::LineId{line};
    refresh();
}

void PanelDock::showDart(quint32 panel, quint32 dart) {
    if (dart != 0 && panel != m_panel.value) {
        showPanel(panel);
    }
    m_dart = patterns::DartId{dart};
    refresh();
}

const patterns::doc::Panel* PanelDock::shown() const {
    return m_document.panel(m_panel);
}

const patterns::doc::InternalLine* PanelDock::shownLine() const {
    const patterns::doc::Panel* p = shown();
    if (p == nullptr || !m_line) {
        return nullptr;
    }
    for (const patterns::doc::InternalLine& line : p->internalLines) {
        if (line.id.value == m_line.value) {
            return &line;
        }
    }
    return nullptr;
}

void PanelDock::emitPlacement(const QString& field) {
    const patterns::doc::Panel* p = shown();
    if (p == nullptr) {
        return;
    }
    // The fields round to 0.1 mm and 0.1°: a field the user left alone keeps its exact value.
    const auto changed = [](const QDoubleSpinBox* field, double shownValue) {
        return std::abs(field->value() - shownValue) >= 0.05;
    };
    const patterns::Placement& now = p->placement;
    patterns::Placement placement = now;
    placement.slot = m_slot->currentText().toStdString();
    if (changed(m_around, now.offset.x() * MM)) {
        placement.offset.x() = m_around->value() / MM;
    }
    if (changed(m_along, now.offset.y() * MM)) {
        placement.offset.y() = m_along->value() / MM;
    }
    if (changed(m_rotation, now.rotation * DEG)) {
        placement.rotation = m_rotation->value() / DEG;
    }
    if (changed(m_clearance, now.clearance * MM)) {
        placement.clearance = m_clearance->value() / MM;
    }
    if (placement.slot != now.slot || placement.offset != now.offset ||
        placement.rotation != now.rotation || placement.clearance != now.clearance) {
        Q_EMIT placeRequested(m_panel.value, placement, field);
    }
}

void PanelDock::refresh() {
    const QSignalBlocker blockers[] = {
        QSignalBlocker(m_name),      QSignalBlocker(m_slot),
        QSignalBlocker(m_around),    QSignalBlocker(m_along),
        QSignalBlocker(m_rotation),  QSignalBlocker(m_clearance),
        QSignalBlocker(m_fabric),    QSignalBlocker(m_particleDistance),
        QSignalBlocker(m_foldAngle), QSignalBlocker(m_dartWidth),
        QSignalBlocker(m_dartDepth)};
    const patterns::doc::Panel* p = shown();
    widget()->setEnabled(p != nullptr);
    m_title->setText(p == nullptr ? tr("Select a panel") : tr("Panel #%1").arg(m_panel.value));
    m_slot->clear();
    m_fabric->clear();
    if (p == nullptr) {
        m_name->clear();
        return;
    }
    m_name->setText(QString::fromStdString(p->name));
    QStringList slotNames = m_slotNames;
    const QString slot = QString::fromStdString(p->placement.slot);
    if (!slotNames.contains(slot)) {
        slotNames.prepend(slot); // the body has no such slot: shown as it is in the file
    }
    m_slot->addItems(slotNames);
    m_slot->setCurrentText(slot);
    m_around->setValue(p->placement.offset.x() * MM);
    m_along->setValue(p->placement.offset.y() * MM);
    m_rotation->setValue(p->placement.rotation * DEG);
    m_clearance->setValue(p->placement.clearance * MM);
    m_particleDistance->setValue(p->particleDistance * MM);
    const patterns::doc::InternalLine* line = shownLine();
    m_foldAngle->setEnabled(line != nullptr);
    m_foldAngle->setValue(line != nullptr ? line->foldAngle * DEG : 0.0);
    const auto dart = patterns::dartSize(*p, m_dart);
    m_dartWidth->setEnabled(dart.has_value());
    m_dartDepth->setEnabled(dart.has_value());
    m_dartWidth->setValue(dart ? dart->width * MM : 0.0);
    m_dartDepth->setValue(dart ? dart->depth * MM : 0.0);
    for (const patterns::GarmentMaterial& m : m_document.materials) {
        const QString name = QString::fromStdString(m.name);
        m_fabric->addItem(name, name);
        if (m.name == p->material) {
            m_fabric->setCurrentIndex(m_fabric->count() - 1);
        }
    }
    for (const QString& preset : m_presetNames) {
        if (m_document.materials.end() == std::find_if(m_document.materials.begin(),
                                                       m_document.materials.end(),
                                                       [&](const patterns::GarmentMaterial& m) {
                                                           return m.name == preset.toStdString();
                                                       })) {
            m_fabric->addItem(tr("%1 (preset)").arg(preset), preset);
            m_fabric->setItemData(m_fabric->count() - 1, true, Qt::UserRole + 1);
        }
    }
}

} // namespace atelier::ui
