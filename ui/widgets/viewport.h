#pragma once
/// The 3D view: the garment and its body drawn by the same renderer, in the same kind of
/// context, as the headless pictures (ui/render: OpenGL 3.3 through EGL, no window surface),
/// shown as an image in a plain widget (docs/decisions/022-viewport-through-egl.md). It redraws
/// when the drape publishes a new snapshot (polled 60 times a second; drawn on a thread of its
/// own while the drape runs, render_thread.h), orbits with the left
/// mouse button, pans with the right (or middle) one and zooms with the wheel; the named views
/// frame the content. Left-dragging the cloth grabs it (the drape runs and follows the mouse
/// in the plane facing the camera); left-dragging elsewhere orbits. Alt+click on the cloth pins
/// the vertex nearest the click where it is now; Alt+click on a pinhead unpins it. Pins are
/// drawn as pinheads (render/pin_markers.h), always visible. Over the cloth: each seam's lines
/// in its pattern colour and, when asked, the strain map with its legend; the panel selected
/// in the pattern is drawn lighter, and pressing the cloth names its panel (panelPicked).

#include "ui/render/camera.h"
#include "ui/render/scene.h"
#include "ui/widgets/drape_controller.h"

#include <QElapsedTimer>
#include <QImage>
#include <QTimer>
#include <QWidget>

class QPainter;

#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace atelier::ui {

class RenderThread;

class Viewport : public QWidget {
    Q_OBJECT
  public:
    explicit Viewport(DrapeController* drape, QWidget* parent = nullptr);
    ~Viewport() override;

    /// Frames the content from a named view.
    void setView(render::View view);
    /// Paints per second over the last second (a new snapshot, an orbit or an expose each).
    double framesPerSecond() const { return m_fps; }
    /// Frames drawn since the view was made (for the responsiveness measure).
    long framesDrawn() const { return m_framesDrawn; }
    /// Wall time of drawing one frame (renderer and read-back), a running mean [ms].
    double drawMilliseconds() const { return m_drawMs; }
    /// The last picture drawn (for File > Save picture and tests).
    QImage picture() const { return m_picture; }
    /// Draws the scene as it is now and waits for the picture (a screenshot, a test): paints
    /// hand their frames to the render thread and show the last picture until it arrives.
    void drawNow();
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
    /// The panel and pattern point [m] of the cloth under `at` (widget coordinates), as drawn
    /// last; nullopt when no cloth is there.
    std::optional<std::pair<QString, Eigen::Vector2d>> patternPointAt(const QPointF& at) const;
    /// While on (the pattern's Seam tool is active), a left press on the cloth picks for the
    /// seam instead of grabbing: seamPointPicked() with the pattern point under the mouse.
    void setSeamPicking(bool on) { m_seamPicking = on; }
    bool seamPicking() const { return m_seamPicking; }
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
    /// Where the selected panel's placement handle is drawn (widget coordinates): the centre of
    /// its cloth as placed on its (highlighted) slot, shown with the slots. Dragging it moves
    /// the panel around and along the slot (placementMoveRequested on release). nullopt when
    /// not shown.
    std::optional<QPointF> placementHandle() const;
    /// The rotation knob above the placement handle (widget coordinates): dragging it round
    /// the handle turns the panel on its slot (placementTurnRequested on release).
    std::optional<QPointF> rotationKnob() const;
    /// Draws slot `name` (the selected panel's) in the highlight colour; empty: none.
    void setHighlightedSlot(const QString& name);
    QString highlightedSlot() const { return m_highlightedSlot; }

    /// Draws `body` (|B|×3 positions, |T|×3 triangles) instead of the drape's body until the
    /// next scene: the Body dock's preview of a body being edited.
    void setPreviewBody(const sim::MatX3& positions, const sim::MatX3i& triangles);
    /// The preview body's vertex count (0: the drape's body is drawn).
    Eigen::Index previewBodyVertices() const { return m_previewBody.rows(); }

    /// Draws panel `name`'s cloth lighter (the panel selected in the pattern); empty: none.
    void setSelectedPanel(const QString& name);
    QString selectedPanel() const { return m_selectedPanel; }
    /// The colour of a selected panel's cloth: its colour, 45% of the way to white.
    static render::Colour selectedColour(const render::Colour& colour);

    /// Colours the cloth by its strain against the pattern (View > Strain map; off by default):
    /// render::triangleStrain of the drawn positions against the pattern coordinates, in
    /// render::strainColours saturating at ±STRAIN_RANGE, and the legend on the picture.
    void setStrainShown(bool shown);
    bool strainShown() const { return m_strainShown; }
    /// Draws every seam's sewn edges, both sides, in the seam's colour (render::seamColour, the
    /// pattern view's), following the cloth as it drapes (View > Seam lines; on by default).
    void setSeamLinesShown(bool shown);
    bool seamLinesShown() const { return m_seamLinesShown; }
    /// The garment's triangle colours as last drawn (|F|): the panels' or the strain map's.
    const std::vector<render::Colour>& garmentColours() const { return m_garmentColours; }
    /// The seam lines as last drawn (one per seam, in StaticScene::seamLines' order); empty when
    /// hidden.
    const std::vector<render::DrawLines>& seamLines() const { return m_seamLines; }

    /// Where the strain colours saturate: ±10% (as `atelier-cli render --overlay strain`).
    static constexpr double STRAIN_RANGE = 0.10;

  Q_SIGNALS:
    /// A slot's marker was clicked (placing the selected panel there is the window's part).
    void slotClicked(const QString& slot);
    /// A left press on panel `name`'s cloth (it is grabbed too): selecting it in the pattern is
    /// the window's part.
    void panelPicked(const QString& name);
    /// The placement handle of panel `name` was dragged: its offset on its slot is to move by
    /// `around` and `along` [m] (the window's part: one undoable placement).
    void placementMoveRequested(const QString& name, double around, double along);
    /// The rotation knob of panel `name` was dragged: its placement's rotation is to change by
    /// `angle` [rad], counter-clockwise seen from outside the slot.
    void placementTurnRequested(const QString& name, double angle);
    /// With seam picking on, a left press on panel `name`'s cloth at pattern point (x, y) [m],
    /// with the keys held (the Seam tool's Shift and Ctrl): picking the outline edge nearest it
    /// is the window's part.
    void seamPointPicked(const QString& name, double x, double y, Qt::KeyboardModifiers modifiers);

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
    /// Waits (the first time) for the render thread's context and renderer; false (with
    /// m_error) when it could not make them.
    bool ensureRenderer();
    /// Draws the scene as it is now into m_picture: at once (`wait`), or on the render thread,
    /// the picture arriving through the event loop (while the drape runs).
    void draw(bool wait);
    /// Marks the picture out of date and schedules a paint that redraws it.
    void requestFrame();

    DrapeController* m_drape;
    std::unique_ptr<RenderThread> m_render;
    std::uint64_t m_framesGiven = 0; ///< frames handed to the render thread
    std::uint64_t m_frameShown = 0;  ///< the latest of them in m_picture
    bool m_rendererChecked = false;  ///< m_render's start() has answered
    bool m_frameInFlight = false;    ///< a frame is being drawn on the render thread
    bool m_frameWanted = false;      ///< the picture is out of date
    bool m_completionPaint = false;  ///< the paint scheduled is for a frame that arrived
    bool m_wasRunning = false;       ///< the drape ran at the last poll (its end asks a frame)
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
    /// The selected panel's cloth centre as placed (start positions) and its slot, when the
    /// slots are shown and both are known.
    std::optional<std::pair<Eigen::Vector3d, patterns::ArrangementSlot>> placementAnchor() const;
    /// A drag of the placement handle: where it started and is now, in the plane through the
    /// anchor that faces the camera [m].
    struct HandleDrag {
        Eigen::Vector3f start;
        Eigen::Vector3f normal;
        Eigen::Vector3f now;
        bool turn = false; ///< the rotation knob: `pressAt` and `at` are what count
        QPointF pressAt;   ///< widget coordinates
        QPointF at;
    };
    std::optional<HandleDrag> m_handleDrag;

    /// The garment's triangle colours for the positions drawn: the strain map's or the panels'.
    std::vector<render::Colour> garmentColoursNow() const;
    /// m_seamLines' positions from m_drawnPositions.
    void followSeamLines();

    sim::MatX3 m_previewBody;
    sim::MatX3i m_previewTriangles;
    QString m_selectedPanel;
    bool m_strainShown = false;
    bool m_seamLinesShown = true;
    std::vector<render::Colour> m_garmentColours;
    std::vector<render::DrawLines> m_seamLines;
    bool m_slotsShown = false;
    bool m_seamPicking = false;
    QString m_highlightedSlot;
    QElapsedTimer m_fpsClock;
    int m_framesThisSecond = 0;
    long m_framesDrawn = 0;
    double m_fps = 0;
    double m_drawMs = 0;
};

} // namespace atelier::ui
