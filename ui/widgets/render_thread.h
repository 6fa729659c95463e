#pragma once
/// The 3D view's renderer on a thread of its own (docs/decisions/022-viewport-through-egl.md):
/// llvmpipe draws on the CPU, and a frame of the 10 mm tshirt takes tens of milliseconds (more
/// while the drape shares the cores), which the event loop must not wait for while the drape
/// runs. The EGL context and the renderer are made on that thread and used only there; jobs run
/// on it one after another, in the order given.

#include "ui/render/renderer.h"

#include <QString>
#include <QThread>

#include <functional>
#include <memory>

class QObject;

namespace atelier::render {
class HeadlessContext;
} // namespace atelier::render

namespace atelier::ui {

class RenderThread {
  public:
    using Job = std::function<void(render::Renderer&)>;

    /// Starts the thread and begins making the context and the renderer there.
    RenderThread();
    /// Waits for the jobs given, releases the renderer and its context on their thread and
    /// stops it.
    ~RenderThread();
    RenderThread(const RenderThread&) = delete;
    RenderThread& operator=(const RenderThread&) = delete;

    /// Waits until the context and the renderer are made on the thread (begun when the thread
    /// was made): empty, or why it cannot draw.
    QString start();
    /// Runs `job` on the thread and waits for it (after the jobs given before it).
    void run(const Job& job);
    /// Runs `job` on the thread without waiting, then `done` on `receiver`'s thread (through
    /// its event loop). `done` is dropped if `receiver` is destroyed first.
    void post(Job job, QObject* receiver, std::function<void()> done);

  private:
    void make(); ///< on the thread
    QThread m_thread;
    QObject* m_worker = nullptr; ///< lives on m_thread; jobs are invoked on it
    std::unique_ptr<render::HeadlessContext> m_context;
    std::unique_ptr<render::Renderer> m_renderer;
    QString m_error;
};

} // namespace atelier::ui
