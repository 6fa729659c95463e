#pragma once
// Outlines for the tests that build their own panels.

#include "patterns/garment.h"

namespace atelier::test {

/// The straight segment from a to b.
inline patterns::Segment line(patterns::Vec2 a, patterns::Vec2 b) {
    patterns::Segment s;
    s.start = a;
    s.end = b;
    return s;
}

/// The circular arc from a to b of bulge tan(sweep/4) (> 0: counter-clockwise).
inline patterns::Segment arc(patterns::Vec2 a, patterns::Vec2 b, double bulge) {
    patterns::Segment s = line(a, b);
    s.kind = patterns::SegmentKind::Arc;
    s.bulge = bulge;
    return s;
}

/// A w × h rectangle [m] from the origin, counter-clockwise, as four line segments.
inline patterns::Loop rectangle(double w, double h) {
    const patterns::Vec2 c[4] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
    patterns::Loop loop;
    for (int k = 0; k < 4; ++k) {
        patterns::Segment s;
        s.start = c[k];
        s.end = c[(k + 1) % 4];
        loop.push_back(s);
    }
    return loop;
}

} // namespace atelier::test
