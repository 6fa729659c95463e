#include "ui/widgets/body_preview.h"

#include "io/body_file.h"

#include <QMetaObject>

#include <filesystem>
#include <utility>

namespace atelier::ui {

BodyPreview::BodyPreview(QObject* parent) : QObject(parent) {
    m_worker = std::thread([this] { loop(); });
}

BodyPreview::~BodyPreview() {
    {
        const std::lock_guard lock(m_mutex);
        m_quit = true;
        m_pending.reset();
    }
    m_wake.notify_all();
    m_worker.join(); // waits for a build under way (a few seconds at most)
}

void BodyPreview::request(const patterns::BodySource& source) {
    {
        const std::lock_guard lock(m_mutex);
        m_pending.emplace(++m_requested, source);
    }
    m_wake.notify_all();
}

void BodyPreview::cancel() {
    const std::lock_guard lock(m_mutex);
    m_pending.reset();
    m_answered = ++m_requested; // a body under way is no longer the latest request
}

void BodyPreview::loop() {
    for (;;) {
        std::pair<std::uint64_t, patterns::BodySource> job;
        {
            std::unique_lock lock(m_mutex);
            m_wake.wait(lock, [this] { return m_quit || m_pending.has_value(); });
            if (m_quit) {
                return;
            }
            job = std::move(*m_pending);
            m_pending.reset();
        }
        // A mesh path is absolute (the window keeps imported bodies so).
        auto body = io::loadBody(job.second, std::filesystem::path(), std::filesystem::path());
        QMetaObject::invokeMethod(
            this,
            [this, id = job.first, source = std::move(job.second), body = std::move(body)] {
                if (id != m_requested) {
                    return; // a newer request is under way: this body is stale
                }
                m_answered = id;
                if (body.ok()) {
                    Q_EMIT built(source, body.value());
                } else {
                    Q_EMIT failed(source, QString::fromStdString(body.error().toString()));
                }
            },
            Qt::QueuedConnection);
    }
}

} // namespace atelier::ui
