#pragma once
/// DXF-AAMA / ASTM D6673 pattern files (ASCII DXF, the exchange format of industrial pattern
/// CAD) imported as an Atelier project: one pattern piece per DXF block, read from the
/// standard's layers: 1 the cut line (the panel's outline), 2 turn points (its corners), 3 curve
/// points, 4 and 80–83 notches, 7 the grain line, 8 internal lines, 11 internal cut-outs (holes),
/// and the piece's system text (`Piece Name:`, `Quantity:`) and the style's (`Units:`).
/// docs/dxf-aama.md describes the mapping; decision 024 why the reader is our own.
///
/// The cut line between two corners is a chain of digitised points; it becomes as few cubic
/// Béziers as stay within `fitTolerance` of every point (lines where the points are straight,
/// arcs where the file has bulges), so that the mesher is not bound to every digitised point.
/// A DXF file has no seams and no 3D placement: the panels are laid on the torso slots, front
/// and back in turn, to be sewn and arranged in the window or the project file.

#include "io/limits.h"
#include "io/result.h"

#include "patterns/project.h"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io {

struct DxfImportOptions {
    /// Fabric preset (assets/materials/fabrics.json) of every panel.
    std::string fabric = "cotton";
    /// Length unit of the file's coordinates: "auto" (the style text `Units: METRIC` is
    /// millimetres, `ENGLISH` inches; else the header's $INSUNITS; else millimetres, with a
    /// warning), or "mm", "cm", "m", "in".
    std::string units = "auto";
    /// Largest distance a fitted outline curve may leave a digitised point of the cut line [m].
    double fitTolerance = 0.0002;
};

/// What became of one DXF block that is a pattern piece.
struct DxfPiece {
    std::string name;         ///< the panel's name (`Piece Name:`, else the block's name)
    std::string block;        ///< the DXF block's name
    int line = 0;             ///< line of the block in the file
    int quantity = 1;         ///< `Quantity:` of the piece system text
    double cutLength = 0;     ///< length of the digitised cut line [m]
    double outlineLength = 0; ///< length of the imported outline [m]
    double fitError = 0;      ///< largest distance of a digitised point from the outline [m]
    int cutPoints = 0;        ///< points of the digitised cut line
    int segments = 0;         ///< segments of the imported outline
    int corners = 0;          ///< corners of the imported outline (turn points)
    int notches = 0;
    int internalLines = 0;
    int holes = 0;
    bool grainLine = false; ///< the grain line was read (else the panel's warp is +y)
};

struct DxfImport {
    patterns::Project project;
    std::vector<DxfPiece> pieces; ///< in project.garment.panels order
    std::string units;            ///< how lengths were read: "mm (Units: METRIC)", ...
    /// What could not be mapped, each naming the piece and the layer or line
    /// (`piece "FRONT": 2 sew lines (layer 14) not imported: seams follow the cut line`).
    std::vector<std::string> warnings;
};

/// Reads a DXF-AAMA file from its text; `file` names it in errors. Bad input is an Error naming
/// the line (`front.dxf: line 120: group code "x1" is not a number`); a file without any block
/// that has a closed cut line is refused; coordinates beyond `limits.maxSceneCoordinate` (once
/// in metres) and pieces beyond patterns::MAX_PANEL_EXTENT are refused.
Result<DxfImport> parseDxfAama(std::string_view text, const std::string& file,
                               const DxfImportOptions& options = {}, const Limits& limits = {});

/// Reads a DXF-AAMA file (a regular file of at most `limits.maxMeshBytes`); the project is named
/// after the file (`shirt.dxf` → `shirt`).
Result<DxfImport> importDxfAama(const std::filesystem::path& path,
                                const DxfImportOptions& options = {}, const Limits& limits = {});

} // namespace atelier::io
