#include "ui/widgets/viewport.h"

#include "ui/render/overlays.h"
#include "ui/render/pin_markers.h"
#include "ui/render/renderer.h"
#include "ui/render/scene.h"
#include "ui/widgets/render_thread.h"

#include <QElapsedTimer>
#include <QImage>
#include <QMouseEvent>
#include <QPainter>
#include <QPolygonF>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace atelier::ui {

namespace {

constexpr float FOV_Y_DEG = 30.0f;
constexpr double DRAFT_SCALE = 0.6;
constexpr float PI = 3.14159265358979f;

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                       const Eigen::Vector3f& up) {
    const Eigen::Vector3f f = (target - eye).normalized();
    const Eigen::Vector3f s = f.cross(up).normalized();
    const Eigen::Vector3f u = s.cross(f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
}

Eigen::Matrix4f perspective(float fovYRad, float aspect, float zNear, float zFar) {
    const float t = 1.0f / std::tan(fovYRad / 2);
    Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
    p(0, 0) = t / aspect;
    p(1, 1) = t;
    p(2, 2) = (zFar + zNear) / (zNear - zFar);
    p(2, 3) = 2 * zFar * zNear / (zNear - zFar);
    p(3, 2) = -1;
    return p;
}

Eigen::AlignedBox3d staticBounds(const StaticScene& s) {
    Eigen::AlignedBox3d box;
    for (Eigen::Index i = 0; i < s.startPositions.rows(); ++i) {
        box.extend(s.startPositions.row(i).transpose());
    }
    for (Eigen::Index i = 0; i < s.bodyPositions.rows(); ++i) {
        box.extend(s.bodyPositions.row(i).transpose());
    }
    return box;
}

/// One frame for the render thread: what changed since the last (copied from the view) and
/// how to draw it; then the picture drawn.
struct FrameJob {
    std::uint64_t number = 0;
    std::optional<render::Scene> scene; ///< the whole scene (then nothing below is updated)
    sim::MatX3 positions;               ///< the garment's, else
    sim::MatX3 normals;
    std::optional<std::vector<render::Colour>> colours; ///< the strain map's
    std::vector<sim::MatX3> linePositions;              ///< the seam lines'
    sim::MatX3 pins;
    render::RenderOptions options;
    render::Camera camera;
    bool strainLegend = false;
    bool draft = false;
    // What the render thread gives back.
    QImage picture;
    QString error;
    double milliseconds = 0;

    void draw(render::Renderer& renderer) {
        QElapsedTimer clock;
        clock.start();
        Result<void> set;
        if (scene) {
            set = renderer.setScene(*scene);
        } else {
            set = renderer.updatePositions(0, positions, normals);
            if (set.ok() && colours) {
                set = renderer.updateTriangleColours(0, *colours);
            }
            for (std::size_t k = 0; set.ok() && k < linePositions.size(); ++k) {
                set = renderer.updateLinePositions(static_cast<int>(k), linePositions[k]);
            }
        }
        renderer.setPins(pins);
        auto image =
            set.ok() ? renderer.render(options, camera) : Result<io::RgbaImage>(set.error());
        if (!image.ok()) {
            error = QString::fromStdString(image.error().toString());
            return;
        }
        io::RgbaImage& img = image.value();
        if (strainLegend) {
            render::drawStrainLegend(img, Viewport::STRAIN_RANGE);
        }
        picture =
            QImage(img.pixels.data(), img.width, img.height, img.width * 4, QImage::Format_RGBA8888)
                .copy();
        milliseconds = double(clock.nsecsElapsed()) * 1e-6;
    }
};

constexpr double SLOT_MARKER_RADIUS_PX = 7;
constexpr double PLACEMENT_HANDLE_RADIUS_PX = 8;
constexpr double ROTATION_KNOB_OFFSET_PX = 36; // above the placement handle

/// A point of the slot's surface at `along` from its origin [m], on its facing meridian: the
/// profile's radius and section centre there (or the slot's radius on its axis).
Eigen::Vector3d slotSurfacePoint(const patterns::ArrangementSlot& slot, double along) {
    double radius = slot.radius;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    if (!slot.profile.empty() && slot.profileStep > 0) {
        const auto k =
            static_cast<std::size_t>(std::clamp((along - slot.alongMin) / slot.profileStep, 0.0,
                                                static_cast<double>(slot.profile.size() - 1)));
        radius = slot.profile[k];
        if (k < slot.profileCentre.size()) {
            centre = slot.profileCentre[k];
        }
    }
    return slot.origin + along * slot.axis + centre + radius * slot.facing;
}

} // namespace

Viewport::Viewport(DrapeController* drape, QWidget* parent) : QWidget(parent), m_drape(drape) {
    setAttribute(Qt::WA_OpaquePaintEvent);
    setMinimumSize(320, 320);
    connect(&m_poll, &QTimer::timeout, this, &Viewport::poll);
    connect(m_drape, &DrapeController::pinsChanged, this, [this] { requestFrame(); });
    m_poll.start(16); // up to 60 frames per second, a frame only for a new snapshot
    m_render = std::make_unique<RenderThread>(); // its context is made while the project opens
    m_fpsClock.start();
}

Viewport::~Viewport() {
    m_render.reset(); // waits for a frame being drawn; its pictures' events go with the view
}

bool Viewport::ensureRenderer() {
    if (m_error.isEmpty() && !m_rendererChecked) {
        m_error = m_render->start();
        m_rendererChecked = true;
    }
    return m_error.isEmpty();
}

void Viewport::requestFrame() {
    m_frameWanted = true;
    update();
}

void Viewport::sceneChanged(bool keepView) {
    m_static = m_drape->staticScene();
    m_snapshot = sim::Snapshot{}; // one of the garment as it was is not drawn over the new one
    m_previewBody.resize(0, 3);   // the new scene has its body
    m_previewTriangles.resize(0, 3);
    m_drawnVersion = 0;
    m_uploaded = false;
    if (keepView) {
        requestFrame();
    } else {
        setView(render::View::ThreeQuarter);
    }
}

void Viewport::setView(render::View view) {
    if (!m_static) {
        requestFrame();
        return;
    }
    const Eigen::AlignedBox3d box = staticBounds(*m_static);
    const double aspect = height() > 0 ? double(width()) / height() : 1.0;
    const render::Camera c = render::frameView(view, box, aspect);
    m_target = box.center().cast<float>();
    const Eigen::Vector3f offset = c.eye - m_target;
    m_distance = offset.norm();
    m_pitch = std::asin(std::clamp(offset.y() / std::max(m_distance, 1e-6f), -1.0f, 1.0f));
    m_yaw = std::atan2(offset.x(), offset.z());
    requestFrame();
}

render::Camera Viewport::camera(float aspect) const {
    const float pitch = std::clamp(m_pitch, -0.49f * PI, 0.49f * PI);
    const Eigen::Vector3f dir(std::cos(pitch) * std::sin(m_yaw), std::sin(pitch),
                              std::cos(pitch) * std::cos(m_yaw));
    render::Camera c;
    c.eye = m_target + m_distance * dir;
    c.view = lookAt(c.eye, m_target, Eigen::Vector3f::UnitY());
    if (aspect <= 0) {
        aspect = height() > 0 ? float(width()) / float(height()) : 1.0f;
    }
    c.projection = perspective(FOV_Y_DEG * PI / 180, aspect, std::max(0.01f, m_distance * 0.01f),
                               m_distance * 10 + 10);
    return c;
}

void Viewport::poll() {
    if (!isVisible()) {
        return;
    }
    if (m_drape->snapshot(m_snapshot) && m_snapshot.version != m_drawnVersion) {
        requestFrame();
    }
    // The drape stopped: the draft drawn while it ran gives way to a full-quality picture.
    const bool running = m_drape->running();
    if (m_wasRunning && !running) {
        requestFrame();
    }
    m_wasRunning = running;
}

void Viewport::drawNow() {
    if (m_static && ensureRenderer()) {
        m_frameWanted = false;
        draw(true);
    }
    update();
}

void Viewport::draw(bool wait) {
    // While the cloth moves, a draft: 0.6 of the resolution (a third of the pixels) and 2×
    // multisampling, scaled up on screen; full resolution and 4× once it stops.
    const bool moving = m_drape->running();
    const qreal ratio = devicePixelRatioF() * (moving ? DRAFT_SCALE : 1.0);
    auto frame = std::make_shared<FrameJob>();
    frame->number = ++m_framesGiven;
    frame->draft = moving;
    const bool live = m_snapshot.version > 0 &&
                      m_snapshot.clothPositions.rows() == m_static->startPositions.rows();
    m_drawnPositions = live ? m_snapshot.clothPositions : m_static->startPositions;
    if (!m_uploaded) {
        // The whole scene once per project: triangles, colours, the body.
        render::Scene scene;
        render::DrawMesh garment;
        garment.kind = render::MeshKind::Garment;
        garment.positions = m_drawnPositions;
        if (live) {
            garment.normals = m_snapshot.clothNormals;
        }
        garment.triangles = m_static->garmentTriangles;
        m_garmentColours = garmentColoursNow();
        garment.triangleColours = m_garmentColours;
        scene.meshes.push_back(std::move(garment));
        render::DrawMesh body;
        body.kind = render::MeshKind::Body;
        const bool preview = m_previewBody.rows() > 0;
        body.positions = preview ? m_previewBody : m_static->bodyPositions;
        body.triangles = preview ? m_previewTriangles : m_static->bodyTriangles;
        body.colour = render::bodyColour();
        scene.meshes.push_back(std::move(body));
        m_seamLines.clear();
        if (m_seamLinesShown) {
            for (const SeamLine& seam : m_static->seamLines) {
                render::DrawLines lines;
                lines.segments = seam.segments;
                lines.colour = render::seamColour(seam.seam);
                lines.widthPx = 3.0f;
                m_seamLines.push_back(std::move(lines));
            }
            followSeamLines();
        }
        scene.lines = m_seamLines;
        frame->scene = std::move(scene);
        m_uploaded = true; // undone if the frame fails
    } else {
        // While the drape runs only the garment's vertices change (and the colours of a strain
        // map, and the seam lines' vertices).
        frame->positions = m_drawnPositions;
        if (live) {
            frame->normals = m_snapshot.clothNormals;
        }
        if (m_strainShown) {
            m_garmentColours = garmentColoursNow();
            frame->colours = m_garmentColours;
        }
        followSeamLines();
        for (const render::DrawLines& lines : m_seamLines) {
            frame->linePositions.push_back(lines.positions);
        }
    }
    m_drawnVersion = live ? m_snapshot.version : 0;
    // Pins still holding at the drawn snapshot's time (a released pin's head goes).
    const std::vector<int> pinned = m_drape->pinnedVertices(live ? m_snapshot.time : 0.0);
    frame->pins.resize(static_cast<Eigen::Index>(pinned.size()), 3);
    Eigen::Index n = 0;
    for (const int v : pinned) {
        if (v >= 0 && v < m_drawnPositions.rows()) {
            frame->pins.row(n++) = m_drawnPositions.row(v);
        }
    }
    frame->pins.conservativeResize(n, 3);
    frame->options.width = std::max(1, int(width() * ratio));
    frame->options.height = std::max(1, int(height() * ratio));
    frame->options.background = {0.93f, 0.93f, 0.94f, 1.0f};
    frame->options.samples = moving ? 2 : 4;
    frame->camera = camera();
    frame->strainLegend = m_strainShown;

    const auto show = [this, frame] {
        if (frame->number < m_frameShown) {
            return; // a later frame (drawn at once) is already shown
        }
        m_frameShown = frame->number;
        ++m_framesDrawn;
        ++m_framesThisSecond;
        if (!frame->error.isEmpty()) {
            m_error = frame->error;
            m_picture = QImage();
            m_uploaded = false;
            return;
        }
        m_drawMs = m_drawMs == 0 ? frame->milliseconds : 0.8 * m_drawMs + 0.2 * frame->milliseconds;
        m_picture = std::move(frame->picture);
        m_picture.setDevicePixelRatio(devicePixelRatioF());
        m_draft = frame->draft;
    };
    if (wait) {
        m_render->run([&](render::Renderer& renderer) { frame->draw(renderer); });
        show();
        return;
    }
    m_frameInFlight = true;
    m_render->post([frame](render::Renderer& renderer) { frame->draw(renderer); }, this,
                   [this, show] {
                       m_frameInFlight = false;
                       show();
                       m_completionPaint = true;
                       update();
                   });
}

QImage Viewport::renderImage(int width, int height, QString* error) {
    const auto fail = [error](const QString& why) {
        if (error != nullptr) {
            *error = why;
        }
        return QImage();
    };
    if (!m_static) {
        return fail(tr("nothing to render: open a project"));
    }
    if (width < 1 || height < 1) {
        return fail(tr("a picture needs at least one pixel"));
    }
    if (!ensureRenderer()) {
        return fail(m_error);
    }
    draw(true); // the scene and its pins as they are now, on the GPU
    if (!m_error.isEmpty()) {
        return fail(m_error);
    }
    render::RenderOptions options;
    options.width = width;
    options.height = height;
    options.background = {0.93f, 0.93f, 0.94f, 1.0f};
    options.samples = 4;
    const render::Camera view = camera(float(width) / float(height));
    Result<io::RgbaImage> image = Error{"", "", "the render thread did not draw"};
    m_render->run([&](render::Renderer& renderer) { image = renderer.render(options, view); });
    if (!image.ok()) {
        return fail(QString::fromStdString(image.error().toString()));
    }
    io::RgbaImage& img = image.value();
    if (m_strainShown) {
        render::drawStrainLegend(img, STRAIN_RANGE);
    }
    return QImage(img.pixels.data(), img.width, img.height, img.width * 4, QImage::Format_RGBA8888)
        .copy();
}

void Viewport::paintEvent(QPaintEvent* /*event*/) {
    QPainter painter(this);
    if (m_static && ensureRenderer()) {
        if (m_frameWanted || !m_completionPaint) {
            // The render thread draws, running or at rest (an orbit, an edit): the picture
            // there is shown until the next one arrives, and a new frame waits for the one
            // being drawn, so the event loop never waits for a draw (drawNow does).
            if (!m_frameInFlight) {
                m_frameWanted = false;
                draw(false);
            } else {
                m_frameWanted = true;
            }
        }
    }
    m_completionPaint = false;
    if (!m_picture.isNull() && m_error.isEmpty()) {
        if (m_draft) {
            painter.setRenderHint(QPainter::SmoothPixmapTransform);
            painter.drawImage(rect(), m_picture);
        } else {
            painter.drawImage(QPointF(0, 0), m_picture);
        }
        paintSlots(painter);
    } else {
        painter.fillRect(rect(), QColor(237, 237, 240));
        painter.setPen(QColor(90, 90, 100));
        painter.drawText(rect().adjusted(20, 20, -20, -20), Qt::AlignCenter | Qt::TextWordWrap,
                         !m_error.isEmpty()
                             ? tr("The 3D view cannot draw: %1").arg(m_error)
                             : tr("Open a garment project (File > Open, or a sample)"));
    }
    if (m_fpsClock.elapsed() >= 1000) {
        m_fps = 1000.0 * m_framesThisSecond / double(m_fpsClock.restart());
        m_framesThisSecond = 0;
    }
}

std::pair<Eigen::Vector3f, Eigen::Vector3f> Viewport::ray(const QPointF& at) const {
    const render::Camera c = camera();
    const Eigen::Matrix4f inverse = (c.projection * c.view).inverse();
    const float x = float(2 * at.x() / std::max(1, width()) - 1);
    const float y = float(1 - 2 * at.y() / std::max(1, height()));
    const Eigen::Vector4f a = inverse * Eigen::Vector4f(x, y, -1, 1);
    const Eigen::Vector4f b = inverse * Eigen::Vector4f(x, y, 1, 1);
    const Eigen::Vector3f origin = a.head<3>() / a.w();
    return {origin, (b.head<3>() / b.w() - origin).normalized()};
}

bool Viewport::pick(const QPointF& at, sim::ClothPoint& point, Eigen::Vector3f& hit) const {
    if (!m_static || m_drawnPositions.rows() != m_static->startPositions.rows()) {
        return false;
    }
    const auto [origin, dir] = ray(at);
    const Eigen::Vector3d o = origin.cast<double>();
    const Eigen::Vector3d d = dir.cast<double>();
    double best = INFINITY;
    const sim::MatX3i& tri = m_static->garmentTriangles;
    for (Eigen::Index t = 0; t < tri.rows(); ++t) {
        // Möller–Trumbore: o + s d = (1-u-v) p0 + u p1 + v p2.
        const Eigen::Vector3d p0 = m_drawnPositions.row(tri(t, 0));
        const Eigen::Vector3d e1 = Eigen::Vector3d(m_drawnPositions.row(tri(t, 1))) - p0;
        const Eigen::Vector3d e2 = Eigen::Vector3d(m_drawnPositions.row(tri(t, 2))) - p0;
        const Eigen::Vector3d p = d.cross(e2);
        const double det = e1.dot(p);
        if (std::abs(det) < 1e-14) {
            continue;
        }
        const Eigen::Vector3d q = o - p0;
        const double u = q.dot(p) / det;
        const Eigen::Vector3d r = q.cross(e1);
        const double v = d.dot(r) / det;
        const double s = e2.dot(r) / det;
        if (u < 0 || v < 0 || u + v > 1 || s <= 0 || s >= best) {
            continue;
        }
        best = s;
        point.triangle = static_cast<int>(t);
        point.barycentric = sim::Vec3(1 - u - v, u, v);
    }
    if (!std::isfinite(best)) {
        return false;
    }
    hit = (o + best * d).cast<float>();
    return true;
}

std::optional<QPointF> Viewport::drawnAt(int vertex) const {
    if (vertex < 0 || vertex >= m_drawnPositions.rows()) {
        return std::nullopt;
    }
    const auto at = render::projectToPixel(camera(), m_drawnPositions.row(vertex).transpose(),
                                           width(), height());
    if (!at) {
        return std::nullopt;
    }
    return QPointF(at->x(), at->y());
}

bool Viewport::togglePinAt(const QPointF& at) {
    // A pinhead under the click unpins (heads are drawn over everything, so they win).
    const double radius = render::pinRadiusPx(height()) + 2;
    int nearest = -1;
    double best = radius;
    for (const int v : m_drape->pinnedVertices()) {
        if (const auto p = drawnAt(v)) {
            const double d = std::hypot(p->x() - at.x(), p->y() - at.y());
            if (d <= best) {
                best = d;
                nearest = v;
            }
        }
    }
    if (nearest >= 0) {
        m_drape->unpin(nearest);
        return true;
    }
    sim::ClothPoint point;
    Eigen::Vector3f hit;
    if (!pick(at, point, hit)) {
        return false;
    }
    int corner = 0;
    point.barycentric.maxCoeff(&corner);
    m_drape->pin(m_static->garmentTriangles(point.triangle, corner));
    return true;
}

std::vector<render::Colour> Viewport::garmentColoursNow() const {
    if (m_strainShown) {
        return render::strainColours(render::triangleStrain(m_drawnPositions,
                                                            m_static->garmentTriangles,
                                                            m_static->patternUvs),
                                     STRAIN_RANGE);
    }
    std::vector<render::Colour> colours(
        static_cast<std::size_t>(m_static->garmentTriangles.rows()));
    for (std::size_t p = 0; p < m_static->panelTriangles.size(); ++p) {
        const auto [first, count] = m_static->panelTriangles[p];
        const bool selected = p < m_static->panelNames.size() && !m_selectedPanel.isEmpty() &&
                              QString::fromStdString(m_static->panelNames[p]) == m_selectedPanel;
        const render::Colour colour = render::panelColour(static_cast<int>(p));
        for (int t = first; t < first + count; ++t) {
            colours[static_cast<std::size_t>(t)] = selected ? selectedColour(colour) : colour;
        }
    }
    return colours;
}

void Viewport::followSeamLines() {
    for (std::size_t k = 0; k < m_seamLines.size() && k < m_static->seamLines.size(); ++k) {
        const std::vector<int>& vertices = m_static->seamLines[k].vertices;
        sim::MatX3& positions = m_seamLines[k].positions;
        positions.resize(static_cast<Eigen::Index>(vertices.size()), 3);
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            positions.row(static_cast<Eigen::Index>(i)) = m_drawnPositions.row(vertices[i]);
        }
    }
}

void Viewport::setPreviewBody(const sim::MatX3& positions, const sim::MatX3i& triangles) {
    m_previewBody = positions;
    m_previewTriangles = triangles;
    m_uploaded = false;
    requestFrame();
}

render::Colour Viewport::selectedColour(const render::Colour& colour) {
    constexpr float LIGHTER = 0.45f;
    return {colour.r + LIGHTER * (1 - colour.r), colour.g + LIGHTER * (1 - colour.g),
            colour.b + LIGHTER * (1 - colour.b), colour.a};
}

void Viewport::setSelectedPanel(const QString& name) {
    if (name != m_selectedPanel) {
        m_selectedPanel = name;
        m_uploaded = false; // the garment's colours change
        requestFrame();
    }
}

void Viewport::setStrainShown(bool shown) {
    if (shown != m_strainShown) {
        m_strainShown = shown;
        m_uploaded = false; // the garment's colours change
        requestFrame();
    }
}

void Viewport::setSeamLinesShown(bool shown) {
    if (shown != m_seamLinesShown) {
        m_seamLinesShown = shown;
        m_uploaded = false; // lines come and go with the scene
        requestFrame();
    }
}

std::optional<std::pair<QString, Eigen::Vector2d>>
Viewport::patternPointAt(const QPointF& at) const {
    sim::ClothPoint point;
    Eigen::Vector3f hit;
    if (!pick(at, point, hit) || m_static->patternUvs.rows() != m_static->startPositions.rows()) {
        return std::nullopt;
    }
    for (std::size_t p = 0; p < m_static->panelTriangles.size() && p < m_static->panelNames.size();
         ++p) {
        const auto [first, count] = m_static->panelTriangles[p];
        if (point.triangle < first || point.triangle >= first + count) {
            continue;
        }
        Eigen::Vector2d uv = Eigen::Vector2d::Zero();
        for (int k = 0; k < 3; ++k) {
            uv +=
                point.barycentric[k] *
                m_static->patternUvs.row(m_static->garmentTriangles(point.triangle, k)).transpose();
        }
        return std::make_pair(QString::fromStdString(m_static->panelNames[p]), uv);
    }
    return std::nullopt;
}

void Viewport::setSlotsShown(bool shown) {
    m_slotsShown = shown;
    requestFrame();
}

std::optional<QPointF> Viewport::slotMarker(const QString& name) const {
    if (!m_slotsShown || !m_static) {
        return std::nullopt;
    }
    for (const patterns::ArrangementSlot& slot : m_static->bodySlots) {
        if (QString::fromStdString(slot.name) == name) {
            const auto at = render::projectToPixel(
                camera(), slotSurfacePoint(slot, 0.5 * (slot.alongMin + slot.alongMax)), width(),
                height());
            if (at) {
                return QPointF(at->x(), at->y());
            }
        }
    }
    return std::nullopt;
}

QString Viewport::slotAt(const QPointF& at) const {
    QString nearest;
    double best = SLOT_MARKER_RADIUS_PX + 2;
    for (const patterns::ArrangementSlot& slot :
         m_static ? m_static->bodySlots : std::vector<patterns::ArrangementSlot>()) {
        const QString name = QString::fromStdString(slot.name);
        if (const auto p = slotMarker(name)) {
            const double d = std::hypot(p->x() - at.x(), p->y() - at.y());
            if (d <= best) {
                best = d;
                nearest = name;
            }
        }
    }
    return nearest;
}

void Viewport::setHighlightedSlot(const QString& name) {
    if (name != m_highlightedSlot) {
        m_highlightedSlot = name;
        requestFrame();
    }
}

std::optional<std::pair<Eigen::Vector3d, patterns::ArrangementSlot>>
Viewport::placementAnchor() const {
    if (!m_slotsShown || !m_static || m_selectedPanel.isEmpty()) {
        return std::nullopt;
    }
    const auto slot = std::find_if(m_static->bodySlots.begin(), m_static->bodySlots.end(),
                                   [&](const patterns::ArrangementSlot& s) {
                                       return QString::fromStdString(s.name) == m_highlightedSlot;
                                   });
    if (slot == m_static->bodySlots.end()) {
        return std::nullopt;
    }
    for (std::size_t p = 0; p < m_static->panelNames.size() && p < m_static->panelTriangles.size();
         ++p) {
        if (QString::fromStdString(m_static->panelNames[p]) != m_selectedPanel) {
            continue;
        }
        const auto [first, count] = m_static->panelTriangles[p];
        if (count <= 0) {
            return std::nullopt;
        }
        Eigen::Vector3d centre = Eigen::Vector3d::Zero();
        for (int t = first; t < first + count; ++t) {
            for (int k = 0; k < 3; ++k) {
                centre +=
                    m_static->startPositions.row(m_static->garmentTriangles(t, k)).transpose();
            }
        }
        return std::pair{centre / (3.0 * count), *slot};
    }
    return std::nullopt;
}

std::optional<QPointF> Viewport::placementHandle() const {
    const auto anchor = placementAnchor();
    if (!anchor) {
        return std::nullopt;
    }
    const auto at = render::projectToPixel(camera(), anchor->first, width(), height());
    return at ? std::optional<QPointF>(QPointF(at->x(), at->y())) : std::nullopt;
}

std::optional<QPointF> Viewport::rotationKnob() const {
    const auto handle = placementHandle();
    return handle ? std::optional<QPointF>(*handle - QPointF(0, ROTATION_KNOB_OFFSET_PX))
                  : std::nullopt;
}

void Viewport::paintSlots(QPainter& painter) const {
    if (!m_slotsShown || !m_static) {
        return;
    }
    painter.setRenderHint(QPainter::Antialiasing);
    const render::Camera c = camera();
    constexpr int SAMPLES = 16;
    for (const patterns::ArrangementSlot& slot : m_static->bodySlots) {
        QPolygonF line;
        for (int k = 0; k <= SAMPLES; ++k) {
            const double along = slot.alongMin + (slot.alongMax - slot.alongMin) * k / SAMPLES;
            if (const auto p =
                    render::projectToPixel(c, slotSurfacePoint(slot, along), width(), height())) {
                line << QPointF(p->x(), p->y());
            }
        }
        const QString name = QString::fromStdString(slot.name);
        const bool highlighted = name == m_highlightedSlot; // the selected panel's
        const QColor colour = highlighted ? QColor(230, 120, 0) : QColor(40, 110, 200);
        painter.setPen(QPen(QColor(colour.red(), colour.green(), colour.blue(), 170),
                            highlighted ? 3 : 2, Qt::DashLine));
        painter.drawPolyline(line);
        if (const auto at = slotMarker(name)) {
            painter.setPen(QPen(colour.darker(130), highlighted ? 2.5 : 1.5));
            painter.setBrush(QColor(255, 255, 255, 220));
            painter.drawEllipse(*at, SLOT_MARKER_RADIUS_PX, SLOT_MARKER_RADIUS_PX);
            painter.drawText(*at + QPointF(SLOT_MARKER_RADIUS_PX + 3, 4), name);
        }
    }
    // The selected panel's placement handle: a diamond, and while dragged a line from where it
    // was to where it goes.
    if (const auto handle = placementHandle()) {
        QPointF at = *handle;
        QPointF knob = *rotationKnob();
        if (m_handleDrag && m_handleDrag->turn) {
            knob = m_handleDrag->at;
        }
        painter.setPen(QPen(QColor(120, 60, 0), 1.5));
        painter.drawLine(*handle, knob);
        painter.setBrush(QColor(255, 255, 255, 230));
        painter.drawEllipse(knob, PLACEMENT_HANDLE_RADIUS_PX - 2, PLACEMENT_HANDLE_RADIUS_PX - 2);
        if (m_handleDrag && !m_handleDrag->turn) {
            const Eigen::Vector3d now = m_handleDrag->now.cast<double>();
            if (const auto p = render::projectToPixel(c, now, width(), height())) {
                at = QPointF(p->x(), p->y());
                painter.setPen(QPen(QColor(230, 120, 0), 2, Qt::DotLine));
                painter.drawLine(*handle, at);
            }
        }
        const double r = PLACEMENT_HANDLE_RADIUS_PX;
        painter.setPen(QPen(QColor(120, 60, 0), 1.5));
        painter.setBrush(QColor(230, 120, 0, 230));
        painter.drawPolygon(QPolygonF(
            {at + QPointF(0, -r), at + QPointF(r, 0), at + QPointF(0, r), at + QPointF(-r, 0)}));
    }
}

void Viewport::mousePressEvent(QMouseEvent* event) {
    m_lastMouse = event->position().toPoint();
    if (event->button() == Qt::LeftButton && event->modifiers() == Qt::NoModifier && m_slotsShown) {
        const auto near = [&](const std::optional<QPointF>& p) {
            return p &&
                   std::hypot(p->x() - event->position().x(), p->y() - event->position().y()) <=
                       PLACEMENT_HANDLE_RADIUS_PX + 2;
        };
        const bool onHandle = near(placementHandle());
        if (onHandle || near(rotationKnob())) {
            const Eigen::Vector3f start = placementAnchor()->first.cast<float>();
            m_handleDrag = HandleDrag{start,
                                      ray(event->position()).second,
                                      start,
                                      !onHandle,
                                      event->position(),
                                      event->position()};
            return;
        }
        if (const QString slot = slotAt(event->position()); !slot.isEmpty()) {
            Q_EMIT slotClicked(slot);
            return;
        }
    }
    if (event->button() == Qt::LeftButton && (event->modifiers() & Qt::AltModifier)) {
        togglePinAt(event->position());
        return;
    }
    if (event->button() == Qt::LeftButton && m_seamPicking) {
        if (const auto at = patternPointAt(event->position())) {
            Q_EMIT seamPointPicked(at->first, at->second.x(), at->second.y(), event->modifiers());
        }
        return; // the Seam tool grabs nothing
    }
    sim::ClothPoint point;
    Eigen::Vector3f hit;
    if (event->button() == Qt::LeftButton && pick(event->position(), point, hit)) {
        for (std::size_t p = 0; p < m_static->panelTriangles.size(); ++p) {
            const auto [first, count] = m_static->panelTriangles[p];
            if (point.triangle >= first && point.triangle < first + count &&
                p < m_static->panelNames.size()) {
                Q_EMIT panelPicked(QString::fromStdString(m_static->panelNames[p]));
            }
        }
        m_grabbing = true;
        m_grabPoint = hit;
        m_grabNormal = ray(event->position()).second;
        m_drape->grab(point, hit.cast<double>());
    }
}

void Viewport::mouseReleaseEvent(QMouseEvent* event) {
    if (event->button() == Qt::LeftButton && m_handleDrag) {
        const HandleDrag drag = *m_handleDrag;
        m_handleDrag.reset();
        requestFrame();
        const auto anchor = placementAnchor();
        const auto handle = placementHandle();
        if (!anchor || !handle) {
            return;
        }
        if (drag.turn) {
            // The knob's turn about the handle on the screen (y down), counter-clockwise
            // positive; seen from inside the slot (the camera behind the panel) the other way.
            const auto screenAngle = [&](const QPointF& p) {
                return std::atan2(-(p.y() - handle->y()), p.x() - handle->x());
            };
            double angle = std::remainder(screenAngle(drag.at) - screenAngle(drag.pressAt),
                                          2 * std::numbers::pi);
            const patterns::ArrangementSlot& slot = anchor->second;
            const Eigen::Vector3d outward =
                anchor->first - slot.origin -
                (anchor->first - slot.origin).dot(slot.axis) * slot.axis;
            if ((camera().eye.cast<double>() - anchor->first).dot(outward) < 0) {
                angle = -angle;
            }
            if (std::abs(angle) > 1e-3) {
                Q_EMIT placementTurnRequested(m_selectedPanel, angle);
            }
            return;
        }
        // Around: along the circle about the slot's axis through the anchor; along: the axis.
        const patterns::ArrangementSlot& slot = anchor->second;
        const Eigen::Vector3d move = (drag.now - drag.start).cast<double>();
        const Eigen::Vector3d fromAxis =
            anchor->first - slot.origin - (anchor->first - slot.origin).dot(slot.axis) * slot.axis;
        const Eigen::Vector3d tangent =
            fromAxis.norm() > 1e-9 ? slot.axis.cross(fromAxis).normalized() : slot.right();
        const double around = move.dot(tangent);
        const double along = move.dot(slot.axis);
        if (std::hypot(around, along) > 1e-4) {
            Q_EMIT placementMoveRequested(m_selectedPanel, around, along);
        }
        return;
    }
    if (event->button() == Qt::LeftButton && m_grabbing) {
        m_grabbing = false;
        m_drape->release();
    }
}

void Viewport::mouseMoveEvent(QMouseEvent* event) {
    const QPoint p = event->position().toPoint();
    const QPoint d = p - m_lastMouse;
    m_lastMouse = p;
    if ((event->buttons() & Qt::LeftButton) && m_handleDrag) {
        m_handleDrag->at = event->position();
        const auto [origin, dir] = ray(event->position());
        const float facing = dir.dot(m_handleDrag->normal);
        if (std::abs(facing) > 1e-6f) {
            const float s = (m_handleDrag->start - origin).dot(m_handleDrag->normal) / facing;
            m_handleDrag->now = origin + s * dir;
            update(); // the handle and its line are painted over the same picture
        }
        return;
    }
    if ((event->buttons() & Qt::LeftButton) && m_grabbing) {
        // The target: where the mouse ray meets the plane through the grabbed point that
        // faces the camera.
        const auto [origin, dir] = ray(event->position());
        const float along = dir.dot(m_grabNormal);
        if (std::abs(along) > 1e-6f) {
            const float s = (m_grabPoint - origin).dot(m_grabNormal) / along;
            m_drape->moveGrab((origin + s * dir).cast<double>());
        }
        return;
    }
    if (event->buttons() & Qt::LeftButton) {
        m_yaw -= 0.01f * float(d.x());
        m_pitch = std::clamp(m_pitch + 0.01f * float(d.y()), -0.49f * PI, 0.49f * PI);
    } else if (event->buttons() & (Qt::RightButton | Qt::MiddleButton)) {
        const render::Camera c = camera();
        const Eigen::Vector3f right = c.view.block<1, 3>(0, 0).transpose();
        const Eigen::Vector3f up = c.view.block<1, 3>(1, 0).transpose();
        const float scale =
            m_distance * 2 * std::tan(FOV_Y_DEG * PI / 360) / float(std::max(1, height()));
        m_target += scale * (-float(d.x()) * right + float(d.y()) * up);
    } else {
        return;
    }
    requestFrame();
}

void Viewport::wheelEvent(QWheelEvent* event) {
    const float steps = float(event->angleDelta().y()) / 120.0f;
    m_distance = std::clamp(m_distance * std::pow(0.9f, steps), 0.05f, 100.0f);
    requestFrame();
}

} // namespace atelier::ui
