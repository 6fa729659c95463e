#pragma once
/// The 3D view: the garment and its body drawn by the same renderer, in the same kind of
/// context, as the headless pictures (ui/render: OpenGL 3.3 through EGL, no window surface),
/// shown as an image in a plain widget (docs/decisions/022-viewport-through-egl.md). It redraws
/// when the drape publishes a new snapshot (polled 30 times a second), orbits with the left
/// mouse button, pans with the right (or middle) one and zooms with the wheel; the named views
/// frame the content. Left-dragging the cloth grabs it (the drape runs and follows the mouse
/// in the plane facing the camera); left-dragging elsewhere orbits. Alt+click on the cloth pins
/// the vertex nearest the click where it is now; Alt+click on a pinhead unpins it. Pins are
/// drawn as pinheads (render/pin_markers.h), always visible.

#include "ui/render/camera.h"
#include "ui/widgets/drape_controller.h"

#include <QElapsedTimer>
#include <QImage>
#include <QTimer>
#include <QWidget>

class QPainter;

#include <memory>
#include <optional>

namespace atelier::render {
class HeadlessContext;
class Renderer;
} // namespace atelier::render

namespace atelier::ui {

class Viewport : public QWidget {
    Q_OBJECT
  public:
    explicit Viewport(DrapeController* drape, QWidget* parent = nullptr);
    ~Viewport() override;

    /// Frames the content from a named view.
    void setView(render::View view);
    /// Paints per second over the last second (a new snapshot, an orbit or an expose each).
    double framesPerSecond() const { return m_fps; }
    /// Wall time of drawing one frame (renderer and read-back), a running mean [ms].
    double drawMilliseconds() const { return m_drawMs; }
    /// The last picture drawn (for File > Save picture and tests).
    QImage picture() const { return m_picture; }
    /// A picture of the scene as it is now, from the view's camera, at `width`×`height` pixels
    /// with 4× multisampling (File > Render image); null when it cannot, with the reason in
    /// `error`.
    QImage renderImage(int width, int height, QString* error = nullptr);
    /// Pins the cloth vertex nearest the garment point under `at` (widget coordinates), or
    /// unpins the pin whose head is under it; what Alt+click does. False when there is neither.
    bool togglePinAt(const QPointF& at);
    /// Where garment vertex `vertex` was drawn last, in widget coordinates; nullopt when it
    /// is not drawn.
    std::optional<QPointF> drawnAt(int vertex) const;
    /// The renderer's error, if it could not start (no OpenGL 3.3).
    QString rendererError() const { return m_error; }

    /// Shows the body's arrangement slots (View > Body slots): each a line down the middle of
    /// the slot's surface, where a panel's centre goes, with a marker and its name at half
    /// height. A left click on a marker emits slotClicked().
    void setSlotsShown(bool shown);
    bool slotsShown() const { return m_slotsShown; }
    /// Where slot `name`'s marker is drawn, in widget coordinates; nullopt when it is not
    /// (hidden, unknown, behind the camera).
    std::optional<QPointF> slotMarker(const QString& name) const;
    /// The slot whose marker is under `at` (widget coordinates), or empty.
    QString slotAt(const QPointF& at) const;
    /// Draws slot `name` (the selected panel's) in the highlight colour; empty: none.
    void setHighlightedSlot(const QString& name);
    QString highlightedSlot() const { return m_highlightedSlot; }

  Q_SIGNALS:
    /// A slot's marker was clicked (placing the selected panel there is the window's part).
    void slotClicked(const QString& slot);

  public Q_SLOTS:
    /// A new static scene (a new project, framed from three-quarter; or an edited garment,
    /// `keepView`: the camera stays where it is).
    void sceneChanged(bool keepView = false);

  protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;

  private:
    void poll();
    /// The view's camera for pictures of this aspect ratio (0: the widget's).
    render::Camera camera(float aspect = 0) const;
    /// The ray under a widget point: origin and unit direction, world [m].
    std::pair<Eigen::Vector3f, Eigen::Vector3f> ray(const QPointF& at) const;
    /// The garment triangle under a widget point, as drawn last: its index, barycentric
    /// coordinates and the world point; false when the ray misses the garment.
    bool pick(const QPointF& at, sim::ClothPoint& point, Eigen::Vector3f& hit) const;
    /// Makes the context and the renderer on first use; false (with m_error) when it cannot.
    bool ensureRenderer();
    /// Draws the scene as it is now into m_picture.
    void draw();

    DrapeController* m_drape;
    std::unique_ptr<render::HeadlessContext> m_context;
    std::unique_ptr<render::Renderer> m_renderer;
    QImage m_picture;
    std::shared_ptr<const StaticScene> m_static;
    sim::Snapshot m_snapshot;
    std::uint64_t m_drawnVersion = 0;
    bool m_draft = false;    ///< m_picture is a reduced-resolution draft (the drape was running)
    bool m_uploaded = false; ///< the static scene is on the GPU (then only positions change)
    QTimer m_poll;
    QString m_error;

    // Orbit camera around m_target: yaw about +y, pitch above the horizon, distance.
    Eigen::Vector3f m_target = Eigen::Vector3f::Zero();
    float m_yaw = 0;      ///< [rad], 0 = looking from +z
    float m_pitch = 0;    ///< [rad]
    float m_distance = 3; ///< [m]
    QPoint m_lastMouse;
    sim::MatX3 m_drawnPositions; ///< the garment as drawn last (picking uses it)
    bool m_grabbing = false;
    Eigen::Vector3f m_grabPoint;  ///< where the grab's plane passes, world [m]
    Eigen::Vector3f m_grabNormal; ///< the plane's normal: the view direction when grabbed

    /// Draws the slots' lines, markers and names over the picture.
    void paintSlots(QPainter& painter) const;

    bool m_slotsShown = false;
    QString m_highlightedSlot;
    QElapsedTimer m_fpsClock;
    int m_framesThisSecond = 0;
    double m_fps = 0;
    double m_drawMs = 0;
};

} // namespace atelier::ui
