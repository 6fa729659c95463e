#include "ui/widgets/fabric_dock.h"

#include "patterns/curve.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>

#include <algorithm>
#include <cmath>

namespace atelier::ui {

namespace {

// The fields show the units fabric data sheets use: g/m², N/m and µN·m.
constexpr double GRAMS = 1000.0;
constexpr double MICRO = 1e6;

bool sameValues(const sim::Material& a, const sim::Material& b) {
    return a.density == b.density && a.stretchWeft == b.stretchWeft &&
           a.stretchWarp == b.stretchWarp && a.shear == b.shear && a.bending == b.bending &&
           a.poisson == b.poisson && a.damping == b.damping;
}

QDoubleSpinBox* valueBox(double min, double max, int decimals, const QString& suffix) {
    auto* box = new QDoubleSpinBox;
    box->setRange(min, max);
    box->setDecimals(decimals);
    box->setSuffix(suffix);
    box->setKeyboardTracking(false);
    return box;
}

} // namespace

double bendingLength(double bending, double density) {
    if (!(bending > 0) || !(density > 0)) {
        return 0;
    }
    return std::cbrt(bending / (density * GRAVITY));
}

FabricDock::FabricDock(QWidget* parent) : QDockWidget(tr("Fabric"), parent) {
    setObjectName("fabric-dock");
    auto* body = new QWidget;
    auto* form = new QFormLayout(body);
    m_chooser = new QComboBox;
    m_preset = new QComboBox;
    m_density = valueBox(1, 2000, 1, tr(" g/m²"));
    m_weft = valueBox(1, 1e7, 0, tr(" N/m"));
    m_warp = valueBox(1, 1e7, 0, tr(" N/m"));
    m_shear = valueBox(1, 1e7, 0, tr(" N/m"));
    m_bending = valueBox(0, 1e6, 2, tr(" µN·m"));
    m_figures = new QLabel;
    m_figures->setWordWrap(true);
    m_figures->setToolTip(tr("Computed from the values above. The bending length takes B as the "
                             "rigidity per unit width; the engine's bending is still a per-hinge "
                             "coefficient (docs/README.md)."));
    form->addRow(tr("Fabric"), m_chooser);
    form->addRow(tr("Preset"), m_preset);
    form->addRow(tr("Density"), m_density);
    form->addRow(tr("Stretch weft"), m_weft);
    form->addRow(tr("Stretch warp"), m_warp);
    form->addRow(tr("Shear"), m_shear);
    form->addRow(tr("Bending"), m_bending);
    form->addRow(m_figures);
    m_measure = new QPushButton(tr("Measure drape"));
    m_measure->setToolTip(tr("The Cusick drape test of these values: a 300 mm specimen on a "
                             "180 mm disc, simulated at 20 mm (a few seconds)"));
    form->addRow(m_measure);
    setWidget(body);
    connect(m_measure, &QPushButton::clicked, this, [this] { startDrapeTest(); });

    connect(m_chooser, &QComboBox::activated, this,
            [this] { showFabric(m_chooser->currentText()); });
    connect(m_preset, &QComboBox::activated, this, [this](int index) {
        const patterns::GarmentMaterial* m = shown();
        const auto preset = m_presets.find(m_preset->itemText(index).toStdString());
        if (m == nullptr || index <= 0 || preset == m_presets.end()) {
            return;
        }
        patterns::GarmentMaterial changed = *m;
        changed.material = preset->second;
        changed.material.name = preset->first;
        Q_EMIT materialRequested(changed);
    });
    for (QDoubleSpinBox* box : {m_density, m_weft, m_warp, m_shear, m_bending}) {
        connect(box, &QDoubleSpinBox::valueChanged, this, [this] { emitValues(); });
    }
    refresh();
}

FabricDock::~FabricDock() {
    stopDrapeTest();
}

patterns::CusickOptions FabricDock::drapeTest() {
    patterns::CusickOptions o;
    o.particleDistance = 0.02; // seconds, not minutes: a figure to compare fabrics by
    o.maxTime = 4;
    o.seed = 1;
    return o;
}

void FabricDock::stopDrapeTest() {
    if (m_drapeThread.joinable()) {
        m_drapeCancel = true;
        m_drapeThread.join();
    }
    m_drapeCancel = false;
}

void FabricDock::startDrapeTest() {
    const patterns::GarmentMaterial* m = shown();
    if (m == nullptr) {
        return;
    }
    stopDrapeTest();
    m_drapeRunning = true;
    const unsigned generation = ++m_drapeGeneration;
    patterns::CusickOptions o = drapeTest();
    o.material = m->material;
    o.cancel = &m_drapeCancel;
    m_drapeThread = std::thread([this, o, generation] {
        const patterns::CusickResult r = patterns::runCusick(o);
        if (r.error == "cancelled") {
            return;
        }
        // Back on the UI thread; dropped if the dock is gone or other values came meanwhile.
        QMetaObject::invokeMethod(
            this,
            [this, r, material = o.material, generation] {
                if (generation != m_drapeGeneration) {
                    return;
                }
                m_drapeFor = material;
                m_drapeKnown = true;
                m_drapeRunning = false;
                m_drapeText = r.error.empty()
                                  ? tr("Drape coefficient (Cusick, 20 mm): %1, %2 nodes")
                                        .arg(r.drapeCoefficient, 0, 'f', 3)
                                        .arg(r.nodes)
                                  : tr("Drape coefficient: not measured (%1)")
                                        .arg(QString::fromStdString(r.error));
                refresh();
                Q_EMIT drapeCoefficientShown();
            },
            Qt::QueuedConnection);
    });
    refresh();
}

void FabricDock::setDocument(const patterns::GarmentDocument& document) {
    m_document = document;
    if (shown() == nullptr) {
        m_fabric = document.materials.empty() ? QString()
                                              : QString::fromStdString(document.materials[0].name);
    }
    refresh();
}

void FabricDock::setPresets(std::map<std::string, sim::Material> presets) {
    m_presets = std::move(presets);
    refresh();
}

void FabricDock::showFabric(const QString& name) {
    m_fabric = name;
    refresh();
}

const patterns::GarmentMaterial* FabricDock::shown() const {
    for (const patterns::GarmentMaterial& m : m_document.materials) {
        if (QString::fromStdString(m.name) == m_fabric) {
            return &m;
        }
    }
    return nullptr;
}

QString FabricDock::figuresText() const {
    return m_figures->text();
}

void FabricDock::emitValues() {
    const patterns::GarmentMaterial* m = shown();
    if (m == nullptr) {
        return;
    }
    // A field left alone keeps the exact value (the fields round it).
    const auto pick = [](const QDoubleSpinBox* field, double value, double scale) {
        const double step = std::pow(10.0, -field->decimals());
        return std::abs(field->value() - value * scale) < 0.5 * step ? value
                                                                     : field->value() / scale;
    };
    patterns::GarmentMaterial changed = *m;
    sim::Material& v = changed.material;
    v.density = pick(m_density, v.density, GRAMS);
    v.stretchWeft = pick(m_weft, v.stretchWeft, 1);
    v.stretchWarp = pick(m_warp, v.stretchWarp, 1);
    v.shear = pick(m_shear, v.shear, 1);
    v.bending = pick(m_bending, v.bending, MICRO);
    const sim::Material& before = m->material;
    if (v.density != before.density || v.stretchWeft != before.stretchWeft ||
        v.stretchWarp != before.stretchWarp || v.shear != before.shear ||
        v.bending != before.bending) {
        v.name = "custom"; // no longer the preset's values
        Q_EMIT materialRequested(changed);
    }
}

void FabricDock::refresh() {
    const QSignalBlocker blockers[] = {QSignalBlocker(m_chooser), QSignalBlocker(m_preset),
                                       QSignalBlocker(m_density), QSignalBlocker(m_weft),
                                       QSignalBlocker(m_warp),    QSignalBlocker(m_shear),
                                       QSignalBlocker(m_bending)};
    m_chooser->clear();
    for (const patterns::GarmentMaterial& m : m_document.materials) {
        m_chooser->addItem(QString::fromStdString(m.name));
    }
    const patterns::GarmentMaterial* m = shown();
    widget()->setEnabled(m != nullptr);
    m_preset->clear();
    m_preset->addItem(tr("(custom values)"));
    for (const auto& [name, material] : m_presets) {
        m_preset->addItem(QString::fromStdString(name));
    }
    if (m == nullptr) {
        m_figures->clear();
        return;
    }
    m_chooser->setCurrentText(m_fabric);
    const int preset = m_preset->findText(QString::fromStdString(m->material.name));
    m_preset->setCurrentIndex(std::max(preset, 0));
    const sim::Material& v = m->material;
    m_density->setValue(v.density * GRAMS);
    m_weft->setValue(v.stretchWeft);
    m_warp->setValue(v.stretchWarp);
    m_shear->setValue(v.shear);
    m_bending->setValue(v.bending * MICRO);
    // Figures computed from the values above (none is a stored or quoted number).
    double area = 0; // the garment's panels cut from this fabric [m²]
    for (const patterns::Panel& p : patterns::toGarment(m_document).panels) {
        if (p.material == m->name) {
            area += std::abs(patterns::loopArea(p.outline));
            for (const patterns::Loop& hole : p.holes) {
                area -= std::abs(patterns::loopArea(hole));
            }
        }
    }
    m_figures->setText(
        tr("Bending length (B/ρg)^⅓: %1 mm\nWeft/warp stretch: %2\nPanels of this fabric: "
           "%3 m², %4 g")
            .arg(bendingLength(v.bending, v.density) * 1000, 0, 'f', 1)
            .arg(v.stretchWeft / v.stretchWarp, 0, 'f', 2)
            .arg(area, 0, 'f', 3)
            .arg(area * v.density * GRAMS, 0, 'f', 0) +
        QStringLiteral("\n") +
        (m_drapeRunning                              ? tr("Drape coefficient: measuring…")
         : m_drapeKnown && sameValues(m_drapeFor, v) ? m_drapeText
                                                     : tr("Drape coefficient: not measured")));
}

} // namespace atelier::ui
