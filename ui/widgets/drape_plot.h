#pragma once
/// A small live plot of the drape over simulated time: the kinetic energy (log scale, left) and
/// the contact count (linear, right), over bands coloured by phase (sewing, settling, at rest).
/// Drawn with QPainter: two series of a few thousand points need no chart library (Qt Charts
/// would be one more package for every build and install).

#include "patterns/drape_session.h"

#include <QWidget>

#include <vector>

namespace atelier::ui {

class DrapePlot : public QWidget {
    Q_OBJECT
  public:
    struct Sample {
        double time = 0;   ///< simulated [s]
        double energy = 0; ///< kinetic [J]
        long contacts = 0;
        patterns::DrapePhase phase = patterns::DrapePhase::Placing;
    };

    explicit DrapePlot(QWidget* parent = nullptr);

    /// Adds a sample; one at an earlier time than the last starts a new drape (a reset, a
    /// garment placed again): the plot is cleared first. Beyond MAX_SAMPLES, every other old
    /// sample is dropped.
    void addSample(const Sample& sample);
    void clear();
    const std::vector<Sample>& samples() const { return m_samples; }

    static constexpr std::size_t MAX_SAMPLES = 4000;

    QSize sizeHint() const override { return {280, 140}; }

  protected:
    void paintEvent(QPaintEvent* event) override;

  private:
    std::vector<Sample> m_samples;
};

} // namespace atelier::ui
