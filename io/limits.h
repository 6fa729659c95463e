#pragma once
/// Bounds on what an input file may ask of Atelier, so that a hostile or mistaken file fails
/// with an error naming the value instead of crashing, hanging or running away with memory.
/// The defaults are far above every sample and documented in docs/file-formats.md; a caller
/// may raise or lower them (the loaders take a `Limits`).

#include <cstdint>

namespace atelier::io {

inline constexpr std::uint64_t MIB = 1024 * 1024;

/// How a message names the thickness limit (its `--limit` name).
inline constexpr const char* THICKNESS_LIMIT = "the limit thickness-m";

struct Limits {
    /// Largest JSON file read (scenes, projects, fabric presets, measurements) [bytes].
    std::uint64_t maxJsonBytes = 64 * MIB;
    /// Largest mesh file read (OBJ cloths, obstacles, body meshes) and DXF pattern [bytes].
    std::uint64_t maxMeshBytes = 256 * MIB;
    /// Deepest nesting of JSON arrays and objects inside each other.
    int maxJsonDepth = 256;
    /// Most vertices of a body mesh read through assimp, every instance of a mesh counted (the
    /// MakeHuman body has 13,380; a dense scan a few million); of a sampled body animation,
    /// every frame counted (20,000,000 vertices are 480 MB of positions).
    long long maxBodyVertices = 20'000'000;
    /// Largest extent (bounding-box side) of a body mesh or an OBJ obstacle [m]; a body is
    /// metres and Y up, so a larger one is a unit mistake or a broken file.
    double maxBodyExtent = 3.0;
    /// Largest coordinate of a generated obstacle shape (plane, sphere, box, capsule) and of
    /// any placed cloth or obstacle, from the origin [m].
    double maxSceneCoordinate = 100.0;
    /// Thickest contact layer of a cloth or an obstacle (scene `thickness`, project
    /// `cloth_thickness_mm` and `body_thickness_mm`) [m]: fabrics are millimetres thick, and a
    /// layer metres thick makes every primitive a contact candidate of every other.
    double maxThickness = 0.05;
    /// Cloths and obstacles in one scene.
    int maxCloths = 256;
    int maxObstacles = 256;
    /// Cloth vertices and triangles over the whole scene (every cloth together).
    long long maxSceneVertices = 4'000'000;
    long long maxSceneTriangles = 8'000'000;
    /// Largest output frame rate of a scene, and sampling rate of a body animation [1/s].
    double maxFrameRate = 1000.0;
    /// Most output frames of a scene (duration × frame rate), and frames sampled from a body
    /// animation.
    long long maxFrames = 100'000;
    /// Most steps the nominal step asks for (scene duration / dt; project time limit / dt):
    /// a run that could not end. Long runs meant to be stopped by hand stay within it.
    long long maxSteps = 1'000'000'000;
    /// Most triangles a project's garment may ask for (panel area over the particle distance).
    long long maxGarmentTriangles = 4'000'000;
};

} // namespace atelier::io
