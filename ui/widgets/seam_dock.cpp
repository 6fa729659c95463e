#include "ui/widgets/seam_dock.h"

#include "patterns/curve.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>
#include <QVBoxLayout>

#include <cmath>
#include <numbers>

namespace atelier::ui {

double seamSideLength(const patterns::GarmentDocument& document,
                      const std::vector<patterns::doc::SeamRange>& side) {
    double total = 0;
    for (const patterns::doc::SeamRange& r : side) {
        const patterns::doc::Panel* p = document.panel(r.panel);
        const int edge = p == nullptr ? -1 : patterns::outlineEdgeIndex(*p, r.edge);
        if (edge >= 0) {
            total += std::abs(patterns::arcLength(
                patterns::contourSegment(p->outline, static_cast<std::size_t>(edge)), r.t0, r.t1));
        }
    }
    return total;
}

SeamDock::SeamDock(QWidget* parent) : QDockWidget(tr("Seam"), parent) {
    setObjectName("seam-dock");
    auto* body = new QWidget;
    auto* layout = new QVBoxLayout(body);
    m_chooser = new QComboBox;
    layout->addWidget(m_chooser);
    for (QLabel*& label : m_sides) {
        label = new QLabel;
        label->setTextInteractionFlags(Qt::TextSelectableByMouse);
        label->setWordWrap(true);
        layout->addWidget(label);
    }
    m_mismatch = new QLabel;
    layout->addWidget(m_mismatch);
    auto* bending = new QFormLayout;
    m_fold = new QDoubleSpinBox;
    m_fold->setRange(-179.9, 179.9);
    m_fold->setDecimals(1);
    m_fold->setSuffix(QStringLiteral(" °"));
    m_fold->setToolTip(tr("Once sewn, the seam rests folded by this angle: 0 = flat, the cloth "
                          "running on across it; positive turns away from side a's front"));
    m_bendingScale = new QDoubleSpinBox;
    m_bendingScale->setRange(0, 100);
    m_bendingScale->setDecimals(2);
    m_bendingScale->setSingleStep(0.5);
    m_bendingScale->setPrefix(QStringLiteral("× "));
    m_bendingScale->setToolTip(tr("Once sewn, the seam's bending rigidity as a multiple of the "
                                  "cloth's: 1 = as the cloth beside it, about 3 for a seam "
                                  "allowance pressed open, 0 = a free hinge"));
    bending->addRow(tr("Fold"), m_fold);
    bending->addRow(tr("Bending"), m_bendingScale);
    layout->addLayout(bending);
    auto* buttons = new QHBoxLayout;
    m_reverse = new QPushButton(tr("Reverse"));
    m_reverse->setToolTip(tr("Sew side b the other way round"));
    m_delete = new QPushButton(tr("Delete"));
    buttons->addWidget(m_reverse);
    buttons->addWidget(m_delete);
    layout->addLayout(buttons);
    layout->addStretch();
    setWidget(body);
    connect(m_chooser, &QComboBox::activated, this,
            [this](int index) { showSeam(patterns::SeamId{m_chooser->itemData(index).toUInt()}); });
    connect(m_reverse, &QPushButton::clicked, this, [this] {
        if (m_seam) {
            Q_EMIT reverseRequested(m_seam.value);
        }
    });
    connect(m_delete, &QPushButton::clicked, this, [this] {
        if (m_seam) {
            Q_EMIT removeRequested(m_seam.value);
        }
    });
    for (QDoubleSpinBox* box : {m_fold, m_bendingScale}) {
        connect(box, &QDoubleSpinBox::editingFinished, this, [this] {
            const patterns::doc::Seam* seam = m_document.seam(m_seam);
            const double fold = m_fold->value() * std::numbers::pi / 180;
            // Only a change is an edit: the values shown round the document's.
            if (seam != nullptr && (std::abs(fold - seam->foldAngle) > 1e-9 ||
                                    m_bendingScale->value() != seam->bendingScale)) {
                Q_EMIT bendingRequested(m_seam.value, fold, m_bendingScale->value());
            }
        });
    }
    refresh();
}

void SeamDock::setDocument(const patterns::GarmentDocument& document) {
    m_document = document;
    if (m_document.seam(m_seam) == nullptr) {
        m_seam = {};
    }
    refresh();
}

void SeamDock::showSeam(patterns::SeamId seam) {
    m_seam = m_document.seam(seam) != nullptr ? seam : patterns::SeamId{};
    refresh();
}

QString SeamDock::sideText(int side) const {
    return m_sides[side == 0 ? 0 : 1]->text();
}

QString SeamDock::mismatchText() const {
    return m_mismatch->text();
}

void SeamDock::refresh() {
    const QSignalBlocker blocker(m_chooser);
    m_chooser->clear();
    m_chooser->addItem(tr("(no seam)"), 0U);
    for (const patterns::doc::Seam& s : m_document.seams) {
        m_chooser->addItem(s.name.empty() ? QStringLiteral("#%1").arg(s.id.value)
                                          : QString::fromStdString(s.name),
                           s.id.value);
        if (s.id == m_seam) {
            m_chooser->setCurrentIndex(m_chooser->count() - 1);
        }
    }
    const patterns::doc::Seam* seam = m_document.seam(m_seam);
    m_reverse->setEnabled(seam != nullptr);
    m_delete->setEnabled(seam != nullptr);
    m_fold->setEnabled(seam != nullptr);
    m_bendingScale->setEnabled(seam != nullptr);
    {
        const QSignalBlocker foldBlocker(m_fold), scaleBlocker(m_bendingScale);
        m_fold->setValue(seam != nullptr ? seam->foldAngle * 180 / std::numbers::pi : 0.0);
        m_bendingScale->setValue(seam != nullptr ? seam->bendingScale : 1.0);
    }
    if (seam == nullptr) {
        for (QLabel* label : m_sides) {
            label->clear();
        }
        m_mismatch->setText(tr("Choose a seam"));
        return;
    }
    const std::vector<patterns::doc::SeamRange>* sides[] = {&seam->a, &seam->b};
    double lengths[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        QStringList lines;
        for (const patterns::doc::SeamRange& r : *sides[k]) {
            const patterns::doc::Panel* p = m_document.panel(r.panel);
            lines << tr("%1, edge #%2, t %3 → %4")
                         .arg(p == nullptr ? tr("(missing panel)")
                                           : QString::fromStdString(p->name))
                         .arg(r.edge.value)
                         .arg(r.t0, 0, 'f', 2)
                         .arg(r.t1, 0, 'f', 2);
        }
        lengths[k] = seamSideLength(m_document, *sides[k]);
        m_sides[k]->setText(tr("Side %1: %2 mm\n%3")
                                .arg(k == 0 ? QStringLiteral("a") : QStringLiteral("b"))
                                .arg(lengths[k] * 1000, 0, 'f', 1)
                                .arg(lines.join('\n')));
    }
    const double mismatch = lengths[0] - lengths[1];
    const bool eased = std::abs(mismatch) > m_document.easeTolerance;
    m_mismatch->setText(tr("Mismatch (a − b): %1 mm%2")
                            .arg(mismatch * 1000, 0, 'f', 1)
                            .arg(eased ? tr(", beyond the %1 mm ease tolerance")
                                             .arg(m_document.easeTolerance * 1000, 0, 'f', 1)
                                       : QString()));
    m_mismatch->setStyleSheet(eased ? "color: #b00000" : "");
}

} // namespace atelier::ui
