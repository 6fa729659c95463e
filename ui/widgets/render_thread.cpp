#include "ui/widgets/render_thread.h"

#include "ui/render/headless_context.h"

#include <QMetaObject>
#include <QObject>

namespace atelier::ui {

RenderThread::RenderThread() {
    m_thread.setObjectName("atelier render");
    m_worker = new QObject;
    m_worker->moveToThread(&m_thread);
    QObject::connect(&m_thread, &QThread::finished, m_worker, &QObject::deleteLater);
    m_thread.start();
    // The context and the renderer (shaders compiled by llvmpipe: ~0.1 s) are made at once, on
    // the thread, so that the first frame does not wait for them.
    QMetaObject::invokeMethod(
        m_worker, [this] { make(); }, Qt::QueuedConnection);
}

RenderThread::~RenderThread() {
    // The renderer's GL objects belong to the context: both released where they were made.
    QMetaObject::invokeMethod(
        m_worker,
        [this] {
            m_renderer.reset();
            m_context.reset();
        },
        Qt::BlockingQueuedConnection);
    m_thread.quit();
    m_thread.wait();
}

QString RenderThread::start() {
    // Waits for the making, queued first.
    QMetaObject::invokeMethod(
        m_worker, [] {}, Qt::BlockingQueuedConnection);
    return m_error;
}

void RenderThread::make() {
    auto context = render::HeadlessContext::create();
    if (!context.ok()) {
        m_error = QString::fromStdString(context.error().toString());
        return;
    }
    m_context = std::move(context.value());
    auto renderer = render::Renderer::create();
    if (!renderer.ok()) {
        m_error = QString::fromStdString(renderer.error().toString());
        return;
    }
    m_renderer = std::move(renderer.value());
}

void RenderThread::run(const Job& job) {
    if (!m_renderer) {
        return;
    }
    QMetaObject::invokeMethod(
        m_worker, [this, &job] { job(*m_renderer); }, Qt::BlockingQueuedConnection);
}

void RenderThread::post(Job job, QObject* receiver, std::function<void()> done) {
    if (!m_renderer) {
        return;
    }
    QMetaObject::invokeMethod(
        m_worker,
        [this, job = std::move(job), receiver, done = std::move(done)]() mutable {
            job(*m_renderer);
            // Events posted to an object that is destroyed are dropped with it.
            QMetaObject::invokeMethod(receiver, std::move(done), Qt::QueuedConnection);
        },
        Qt::QueuedConnection);
}

} // namespace atelier::ui
