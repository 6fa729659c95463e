#pragma once
/// Draping a project from the command line (drape_command.cpp): `atelier-cli drape`, and the
/// drape behind `atelier-cli render PROJECT.atelier`.

#include "app/cli/preflight.h"

#include "io/obj.h"

#include "patterns/drape_session.h"

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace atelier::app {

struct DrapeOptions {
    std::string project;
    std::string out;
    std::string report;
    std::string thumbnail; ///< a 256×256 three-quarter PNG of the drape, or empty
    /// The same surface in further files, each in the format of its extension (--also-out).
    std::vector<std::string> alsoOut;
    int threads = 0;
    double timeLimit = -1;          ///< override of the project's time limit [s]; < 0 = keep
    double particleDistanceMm = -1; ///< override of the project's particle distance [mm]
    std::string linearSolver;       ///< override of the project's linear solver; empty = keep
    std::string framesDir;          ///< write the garment at every frame here (OBJ)
    std::string format;             ///< --out's format (io::parseMeshFormat); empty = by extension
    bool splitPanels = false;       ///< --out keeps each panel's own vertices along the seams
    bool interactive = false;       ///< the window's step (patterns::interactiveStep)
    bool settlingStep = true;       ///< --interactive: one step a frame once sewn and slow
    long maxVertices = DEFAULT_MAX_VERTICES; ///< refuse meshes estimated larger
    std::vector<std::string> limits;         ///< --limit NAME=VALUE
    /// Further files written once the drape ends (a caller's pictures), checked with the
    /// other outputs before any work.
    std::vector<NamedPath> laterOutputs;
    /// The body to drape on instead of the project's (`atelier-cli animate`: the first frame
    /// of a sampled animation, with its slots); empty = the project's.
    std::optional<patterns::Body> body;
};

/// Called once the drape has ended with a finite state, after its files are written: what the
/// caller does with it (it may drape on: `atelier-cli animate`); returns the exit code to go on
/// with (given the drape's `code`).
using DrapeFinished = std::function<int(patterns::DrapeSession& session, int code)>;

/// Drapes `options.project` (meshes, places, sews, drapes until rest or the time limit, as
/// `atelier-cli drape`), prints progress and problems on stderr, writes the outputs asked for
/// and returns the exit code (commands.h).
int runDrape(const DrapeOptions& options, const DrapeFinished& finished = {});

/// `DRAPED.obj` → `DRAPED.body.obj`: where `drape --out DRAPED.obj` writes the body.
std::filesystem::path drapedBodyPath(const std::filesystem::path& out);

/// The draped garment as one OBJ: triangles offset per panel, pattern coordinates as UVs, one
/// group per panel.
struct GarmentObj {
    sim::MatX3i triangles;
    io::ObjWriteOptions options;
};
GarmentObj garmentObj(const patterns::Garment& garment, const patterns::GarmentMesh& mesh,
                      const patterns::AssembledGarment& assembled);

} // namespace atelier::app
