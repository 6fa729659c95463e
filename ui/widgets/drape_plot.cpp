#include "ui/widgets/drape_plot.h"

#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>

namespace atelier::ui {

namespace {

QColor phaseColour(patterns::DrapePhase phase) {
    switch (phase) {
    case patterns::DrapePhase::Sewing:
        return {255, 236, 200};
    case patterns::DrapePhase::Settling:
        return {214, 232, 255};
    case patterns::DrapePhase::AtRest:
        return {214, 245, 214};
    case patterns::DrapePhase::Failed:
        return {255, 210, 210};
    default:
        return {240, 240, 240};
    }
}

const QColor ENERGY_COLOUR(200, 60, 40);
const QColor CONTACT_COLOUR(40, 90, 190);

} // namespace

DrapePlot::DrapePlot(QWidget* parent) : QWidget(parent) {
    setMinimumSize(200, 110);
    setToolTip(tr("Kinetic energy [J] (red, log scale, left) and contacts (blue, right) over "
                  "simulated time; the background is the phase: sewing (orange), settling "
                  "(blue), at rest (green)"));
}

void DrapePlot::clear() {
    m_samples.clear();
    update();
}

void DrapePlot::addSample(const Sample& sample) {
    if (!std::isfinite(sample.time) || !std::isfinite(sample.energy)) {
        return;
    }
    if (!m_samples.empty() && sample.time < m_samples.back().time) {
        m_samples.clear();
    }
    if (!m_samples.empty() && sample.time == m_samples.back().time) {
        m_samples.back() = sample; // the drape has not stepped since: the newest figures
    } else {
        m_samples.push_back(sample);
    }
    if (m_samples.size() > MAX_SAMPLES) { // halve the history's resolution, keep the newest
        std::vector<Sample> kept;
        kept.reserve(MAX_SAMPLES / 2 + 1);
        for (std::size_t i = 0; i + 1 < m_samples.size(); i += 2) {
            kept.push_back(m_samples[i]);
        }
        kept.push_back(m_samples.back());
        m_samples = std::move(kept);
    }
    update();
}

void DrapePlot::paintEvent(QPaintEvent* /*event*/) {
    QPainter painter(this);
    painter.fillRect(rect(), palette().base());
    const QFontMetrics metrics(font());
    const int margin = metrics.height();
    const QRectF plot =
        QRectF(rect()).adjusted(margin * 2.5, margin * 0.5, -margin * 2.5, -margin * 1.5);
    if (m_samples.empty() || plot.width() < 10 || plot.height() < 10) {
        painter.setPen(palette().text().color());
        painter.drawText(rect(), Qt::AlignCenter, tr("Kinetic energy and contacts while draping"));
        return;
    }
    const double t0 = m_samples.front().time;
    const double t1 = std::max(m_samples.back().time, t0 + 1e-3);
    // Energy on a log scale over the decades it spans (at least two), contacts from 0.
    double eMax = 1e-12;
    double eMin = INFINITY;
    long cMax = 1;
    for (const Sample& s : m_samples) {
        eMax = std::max(eMax, s.energy);
        if (s.energy > 0) {
            eMin = std::min(eMin, s.energy);
        }
        cMax = std::max(cMax, s.contacts);
    }
    const double logMax = std::ceil(std::log10(eMax));
    const double logMin = std::min(logMax - 2, std::floor(std::log10(std::min(eMin, eMax))));
    const auto x = [&](double t) { return plot.left() + (t - t0) / (t1 - t0) * plot.width(); };
    const auto yEnergy = [&](double e) {
        const double l = e > 0 ? std::clamp(std::log10(e), logMin, logMax) : logMin;
        return plot.bottom() - (l - logMin) / (logMax - logMin) * plot.height();
    };
    const auto yContacts = [&](long c) {
        return plot.bottom() - double(c) / double(cMax) * plot.height();
    };

    // Phase bands.
    for (std::size_t i = 0; i < m_samples.size();) {
        std::size_t j = i;
        while (j + 1 < m_samples.size() && m_samples[j + 1].phase == m_samples[i].phase) {
            ++j;
        }
        const double right = j + 1 < m_samples.size() ? m_samples[j + 1].time : t1;
        painter.fillRect(
            QRectF(QPointF(x(m_samples[i].time), plot.top()), QPointF(x(right), plot.bottom())),
            phaseColour(m_samples[i].phase));
        i = j + 1;
    }
    painter.setPen(palette().mid().color());
    painter.drawRect(plot);

    painter.setRenderHint(QPainter::Antialiasing);
    QPainterPath energy, contacts;
    for (std::size_t i = 0; i < m_samples.size(); ++i) {
        const Sample& s = m_samples[i];
        const QPointF e(x(s.time), yEnergy(s.energy));
        const QPointF c(x(s.time), yContacts(s.contacts));
        i == 0 ? energy.moveTo(e) : energy.lineTo(e);
        i == 0 ? contacts.moveTo(c) : contacts.lineTo(c);
    }
    painter.setBrush(Qt::NoBrush);
    painter.setPen(QPen(CONTACT_COLOUR, 1.5));
    painter.drawPath(contacts);
    painter.setPen(QPen(ENERGY_COLOUR, 1.5));
    painter.drawPath(energy);

    // Axes' labels: energy decades left, contacts right, time below.
    painter.setPen(ENERGY_COLOUR);
    for (const double l : {logMin, logMax}) {
        painter.drawText(
            QRectF(0, yEnergy(std::pow(10.0, l)) - margin / 2.0, plot.left() - 3, margin),
            Qt::AlignRight | Qt::AlignVCenter, QStringLiteral("1e%1").arg(l));
    }
    painter.setPen(CONTACT_COLOUR);
    for (const long c : {0L, cMax}) {
        painter.drawText(
            QRectF(plot.right() + 3, yContacts(c) - margin / 2.0, margin * 2.4, margin),
            Qt::AlignLeft | Qt::AlignVCenter, QString::number(c));
    }
    painter.setPen(palette().text().color());
    painter.drawText(QRectF(plot.left(), plot.bottom(), plot.width(), margin * 1.5),
                     Qt::AlignCenter, tr("t %1–%2 s").arg(t0, 0, 'f', 2).arg(t1, 0, 'f', 2));
}

} // namespace atelier::ui
