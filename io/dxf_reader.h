#pragma once
/// ASCII DXF read as the shapes of its blocks: a streaming group-code reader (pairs of lines: a
/// code, then its value) that keeps only what a pattern needs: `POLYLINE`/`VERTEX`/`SEQEND`,
/// `LWPOLYLINE`, `LINE` and `POINT` on numbered layers (bulges kept), `TEXT`/`MTEXT`, and the
/// header's `$INSUNITS`; every other entity and section is skipped. Errors name the line.
/// io/dxf_aama.h maps the shapes to pattern pieces (decision 024).

#include "io/result.h"

#include "sim/core/types.h"

#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io {

/// Most points kept from one file: far above any pattern (a style's pieces have a few
/// thousand), and a bound on memory for a hostile file.
inline constexpr long long DXF_MAX_POINTS = 2'000'000;
/// Most points of one polyline.
inline constexpr long long DXF_MAX_POLYLINE_POINTS = 200'000;

/// A polyline, line or point of a block on a numbered layer, in the file's units.
struct DxfShape {
    int layer = -1;
    int line = 0; ///< the entity's line in the file
    std::vector<sim::Vec2> points;
    std::vector<double> bulges; ///< per point: the bulge of the span that starts there
    bool closed = false;
    bool isPoint = false;
};

struct DxfBlock {
    std::string name;
    int line = 0;
    std::vector<DxfShape> shapes;
    std::vector<std::string> texts; ///< TEXT and MTEXT, formatting codes removed
};

struct DxfDrawing {
    std::vector<DxfBlock> blocks;        ///< blocks whose name does not start with '*'
    std::vector<std::string> styleTexts; ///< TEXT and MTEXT outside blocks
    int insUnits = 0;                    ///< the header's $INSUNITS (0: none)
    std::set<std::string> otherLayers;   ///< layer names that are not numbers (up to 20)
};

/// A DXF value without its surrounding blanks (and a CR of CRLF line ends).
std::string_view dxfTrimmed(std::string_view s);
/// A value as an error message quotes it: at most 60 characters, control characters as '?'.
std::string dxfShown(std::string_view s);

/// Reads the blocks of an ASCII DXF text; `file` names it in errors (`a.dxf: line 12: ...`).
Result<DxfDrawing> readDxfDrawing(std::string_view text, const std::string& file);

} // namespace atelier::io
