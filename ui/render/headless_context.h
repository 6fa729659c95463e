#pragma once
/// An OpenGL 3.3 core context with no window and no display, through EGL: Mesa's surfaceless
/// platform, or else an EGL device (Mesa's software device, or a GPU). The EGL calls live in
/// egl_context.cpp alone.

#include "sim/core/result.h"

#include <memory>
#include <string>

namespace atelier::render {

class HeadlessContext {
  public:
    /// Creates the context and makes it current on the calling thread. The error says what is
    /// missing and which packages provide it (never a context that would draw black pictures).
    static Result<std::unique_ptr<HeadlessContext>> create();
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    /// Which EGL platform gave the context: "surfaceless" or "device".
    const std::string& platform() const;

  private:
    struct Impl;
    explicit HeadlessContext(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

} // namespace atelier::render
