#pragma once
/// Builds bodies off the UI thread for the Body dock's live preview: a mannequin takes 1.2–4 s
/// (docs/benchmarks.md, "The mannequin") to generate, so one worker thread builds the latest body
/// asked for; a body asked for while another builds replaces the request, and a result that is no
/// longer the latest is dropped.

#include "patterns/body.h"
#include "patterns/project.h"

#include <QObject>
#include <QString>

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <thread>

namespace atelier::ui {

class BodyPreview : public QObject {
    Q_OBJECT
  public:
    explicit BodyPreview(QObject* parent = nullptr);
    ~BodyPreview() override;
    BodyPreview(const BodyPreview&) = delete;
    BodyPreview& operator=(const BodyPreview&) = delete;

    /// Builds `source`'s body (a mannequin; a mesh is read as a project reads it) on the
    /// worker; built() or failed() follow unless another request comes first.
    void request(const patterns::BodySource& source);
    /// Drops the request under way or waiting: no built() or failed() for it (another
    /// project was opened).
    void cancel();
    /// Requests made so far; each built() or failed() names the one it answers.
    std::uint64_t requests() const { return m_requested; }
    /// Whether the latest request has been answered.
    bool idle() const { return m_answered == m_requested; }

  Q_SIGNALS:
    /// The latest request's body, built (UI thread).
    void built(const patterns::BodySource& source, const patterns::Body& body);
    /// The latest request could not be built: the message says why (UI thread).
    void failed(const patterns::BodySource& source, const QString& message);

  private:
    void loop();

    std::mutex m_mutex;
    std::condition_variable m_wake;
    std::optional<std::pair<std::uint64_t, patterns::BodySource>> m_pending; ///< m_mutex
    bool m_quit = false;                                                     ///< m_mutex
    std::uint64_t m_requested = 0;                                           ///< UI thread
    std::uint64_t m_answered = 0;                                            ///< UI thread
    std::thread m_worker;
};

} // namespace atelier::ui
