#pragma once
/// Runs one fuzz case, in the forked child: loads the main file with the public io loader and,
/// when it loads, runs it as the command line would, bounded (a few engine steps of a scene; a
/// drape session prepared at a coarse particle distance and stepped a few times).

#include "patterns/body.h"
#include "patterns/project.h"

#include "fuzz_case.h"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace atelier::fuzz {

/// How a case ended, as the child's exit status. Any other status (a signal, a sanitizer
/// report) is a failure too.
enum class CaseEnd : int {
    Ran = 0,         ///< loaded and ran
    Refused = 10,    ///< refused with an io::Error (or a simulation error) that says why
    TooLarge = 11,   ///< loaded, but above RunLimits: not run (not a failure)
    EmptyError = 20, ///< refused with an empty message: a failure
    Exception = 21,  ///< an exception left the loader or the run: a failure
    Stalled = 22,    ///< stepping made no progress in time: the command line would loop forever
};

/// Whether a child's exit status is one of the two expected outcomes (or a skipped run).
bool passed(int exitStatus);

/// Caps that keep a case to milliseconds or a fraction of a second.
struct RunLimits {
    int steps = 3;                        ///< engine or drape steps after a load
    long maxVertices = 4000;              ///< scenes with more cloth vertices are not run
    long maxObstacleTriangles = 60000;    ///< nor with more obstacle triangles
    double minParticleDistance = 0.03;    ///< projects are meshed this coarse at least [m]
    double maxTriangleEstimate = 40000;   ///< larger garments are not draped ...
    double runawayTriangleEstimate = 1e7; ///< ... unless beyond any garment: then they must be
                                          ///< refused, and are run to see that they are
};

/// Bodies built once, before any child is forked, for the body sources of the seed projects:
/// every child inherits them instead of building the mannequin again.
class BodyCache {
  public:
    /// Builds the mannequin of every distinct source (mesh bodies are left to the loader).
    void add(const patterns::BodySource& source);
    /// The body built for `source`, or nullptr.
    const patterns::Body* find(const patterns::BodySource& source) const;

  private:
    std::vector<std::pair<patterns::BodySource, patterns::Body>> m_bodies;
};

/// Loads `mainFile` as `kind` and runs it within `limits`. `message` says what happened (the
/// error, or what ran). Returns the child's exit status.
int runCase(InputKind kind, const std::filesystem::path& mainFile, const BodyCache& bodies,
            const RunLimits& limits, std::string& message);

} // namespace atelier::fuzz
