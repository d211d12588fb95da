// The GL side of `yarnvox view`: the renderers of inspect kept alive between
// frames (the bricks loaded into the atlas once, the slices uploaded once),
// and one frame drawn from a view state. A garment's frame is two pictures
// side by side with one camera: its slices on the left, the ray cast (or the
// mode chosen) of its voxelization on the right. A view of two volumes
// (--beside) draws the second on the right in the same mode, from the
// same camera: the same place in the world where both say where they lie,
// else each framed alike in its own box. Everything here runs on the
// one render thread that made the scene (the GL context is current there).
#pragma once

#include "inspect/render_request.h"
#include "render/render_context.h"
#include "render/renderer.h"
#include "view/view_message.h"
#include "view/view_region.h"
#include "view/view_volume.h"
#include "view/view_voxelizer.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace yv {

/// What one frame shows.
struct ViewState {
    ViewCamera camera;
    std::string mode = "raycast";
    int width = 960, height = 540;
    /// A garment's view: the ray cast blended over the slices in one picture
    /// (the paper's Figure 3) rather than beside them.
    bool blend = false;
    /// The ray cast's transfer function: a preset and its opacity scale (withOpacityScale).
    std::string transfer = "fibre";
    double opacity = 1.0;
    /// The yarn twist, radians per world unit: the slices' shading and the
    /// view voxelizations (ViewScene::twist() unless the page sets it).
    double twist = 0.0;
    /// The camera is moving (the page says so while input goes on): a
    /// frame late for the slices' time draws fewer of them, where `degrade`.
    bool moving = false;
    /// Frames drawn while moving may degrade (the page's switch: false draws every frame at full quality).
    bool degrade = true;
    bool operator==(const ViewState&) const = default;
};

/// How the view draws: the slices' level of detail, and what a moving camera may give up.
/// The most levels a moving frame's volume is drawn coarser than the budget's.
constexpr int kMaxMovingCoarser = 3;

struct ViewQuality {
    /// --slice-lod: the level of detail, in pixels (SliceSettings::lodPixels),
    /// of every frame once the camera stops.
    double lodPixels = kDefaultSliceLodPixels;
    /// --slice-primitive: how the slices' slabs are drawn (SliceSettings::primitive).
    SlicePrimitive slicePrimitive = SlicePrimitive::Auto;
    /// --moving-ms: while the camera moves (and the page lets frames
    /// degrade), each half of a frame may take this long: slices that took
    /// longer double the level of detail of the next frame's (1, 2, 4, ...
    /// 64 pixels: fewer slabs), a volume that took longer is drawn a level
    /// coarser next (up to kMaxMovingCoarser); a part that took under a
    /// quarter of it goes back a step. Half of a frame at 60 a second by default.
    double movingSeconds = 0.008;
};

/// One frame drawn, with what the page's overlay shows about it.
struct ViewFrame {
    RgbImage image;
    double renderSeconds = 0.0; ///< the frame's host and GPU work, readback included
    double drawSeconds = 0.0;   ///< the renderers' draw calls to glFinish (the slices' also their sort)
    int level = 0;              ///< the level of detail drawn
    std::uint64_t slices = 0, gpuBytes = 0;
    std::string slicePrimitive; ///< how the slices were drawn (RenderReport::slicePrimitive); empty: no slices
    /// The slices' level of detail drawn, in pixels (-1: no slices drawn), and
    /// whether it was coarser than ViewQuality::lodPixels because the camera moved.
    double sliceLod = -1.0;
    bool degraded = false;
    /// Levels of detail the volume was drawn coarser than the GPU budget holds, because the camera moved.
    int coarserLevels = 0;
    std::uint64_t detail = 0;   ///< the view voxelization drawn (its id; 0: the volume opened)
    long long gpuFreeBytes = -1; ///< the GPU's free memory after the frame (-1: the driver does not say)
    /// Where a frame that first draws a volume or mode spent its setup (0 otherwise):
    /// opening a view voxelization's .vdb, loading atlases, making renderers.
    double openSeconds = 0.0, atlasSeconds = 0.0, rendererSeconds = 0.0;
};

class ViewScene {
  public:
    /// Takes the opened volume; makes the GL context on `device` on the
    /// calling thread and loads the atlas (the level `gpuBudgetBytes` holds).
    /// Frames are drawn as `quality` says. Throws yv::Error (no GL
    /// context, a budget that holds no level).
    /// `beside`: a second volume drawn on the right (its atlas loaded now too).
    ViewScene(ViewVolume volume, int device, std::uint64_t gpuBudgetBytes, ViewQuality quality = {},
              std::optional<ViewVolume> beside = std::nullopt);
    ~ViewScene();

    /// The modes one key away, in key order ("raycast" first).
    const std::vector<std::string>& modes() const { return modes_; }
    /// Two pictures side by side: a garment's slices and its voxels, or two volumes.
    bool sideBySide() const { return beside_ != nullptr || (volume_.garment && volume_.slices.has_value()); }
    /// The ray cast may be blended over the slices (a garment's view, no second volume).
    bool blends() const { return beside_ == nullptr && sideBySide(); }
    const ViewVolume& volume() const { return volume_; }
    /// The second volume, drawn on the right (nullptr: none).
    const ViewVolume* beside() const { return beside_.get(); }
    /// The GL renderer's name.
    const std::string& renderer() const { return rendererName_; }
    /// The transfer-function presets a page may pick (transferFunctionPresets()).
    const std::vector<std::string>& transferPresets() const;
    /// Whether a page may change the twist: the garment's place in the world
    /// is known (its slices are drawn or its view voxelized).
    bool twistable() const { return volume_.grid.has_value(); }
    /// The twist the garment was sliced and voxelized with, radians per world unit.
    double twist() const { return volume_.twist; }

    /// Draws `state` (its mode one of modes()). Throws yv::Error on a GL error.
    ViewFrame render(const ViewState& state);

    /// Voxelize what the camera sees: runs go to `voxelizer` (owned by the
    /// caller, outliving the scene's use of it). Without one, or without the
    /// volume's place in the world, the view cannot (voxelizeInView says so).
    void attachVoxelizer(ViewVoxelizer* voxelizer) { voxelizer_ = voxelizer; }
    /// Asks for what `state`'s camera sees (the ray cast's half of a
    /// side-by-side view), at about a voxel a pixel within `maxSideVoxels` a
    /// side; once run, it is drawn in place of the volume opened whenever
    /// the camera sees no more than its box. The JSON text for the page.
    /// Throws yv::Error when the view cannot or nothing is in view.
    std::string voxelizeInView(const ViewState& state, int maxSideVoxels);
    /// Saves the view voxelization taken last (a .vdb, or a work directory).
    /// Throws yv::Error when there is none.
    std::string saveView(bool workDir);
    /// The view voxelization taken last, if any.
    const DetailRun* detail() const;
    /// The width of a pixel at the point `state`'s camera looks at: world
    /// units where the volume's place in the world is known (`world` true),
    /// else voxels. What the page's ruler measures with.
    double pixelSize(const ViewState& state, bool& world) const;

  private:
    /// The renderers of one volume drawn in the ray-cast half, and where its
    /// voxels lie against the volume opened: detail = scale * opened + offset.
    struct VolumeLayer {
        const VolumeSource* source = nullptr;
        BrickCache* cache = nullptr;
        VoxelBox box;
        double scale = 1.0;
        glm::dvec3 offset{0.0};
        std::map<std::string, std::unique_ptr<Renderer>> renderers;
        std::map<std::string, AtlasLoad> atlases; ///< by mode: the one its renderer draws
        std::map<std::string, std::pair<std::string, double>> looks; ///< by mode: the transfer function its renderer has
        /// Atlases of coarser levels drawn while the camera moves, apart from
        /// the fine ones: a new one drops every coarse renderer of the layer
        /// (the cache may have let go of the atlas one drew).
        std::unique_ptr<BrickCache> coarse;
    };
    struct DetailLayer;
    struct BesideLayer;

    /// The renderer of `mode` on `layer`, its atlas `coarser` levels coarser than the budget's (0: the budget's).
    Renderer& rendererFor(VolumeLayer& layer, const std::string& mode, ViewFrame& frame, int coarser = 0);
    VolumeLayer& layerFor(const std::string& mode, const ViewCamera& view, int width, int height);
    /// A picture of a frame queued on the GPU, and what taking it back
    /// needs: a frame queues both its halves before it reads either, so
    /// that the GPU draws the second while the host takes the first.
    struct QueuedPicture {
        VolumeLayer* layer = nullptr;
        std::string key; ///< its renderer's (rendererKey)
        bool slices = false, degrading = false;
        int coarser = 0, x0 = 0;
        std::unique_ptr<PictureInFlight> inFlight;
    };
    /// Queues `mode` of `layer` (by default the volume opened, or the view's
    /// run where it holds what the camera sees), `width` x `height`, for
    /// column `x0` of the frame.
    QueuedPicture queuePicture(const ViewState& state, const std::string& mode, int width, int height, int x0,
                               ViewFrame& frame, VolumeLayer* layer = nullptr);
    /// Waits for `picture` and puts it into `out` at its column; counts it
    /// into `frame`, and adapts the moving levels of detail to its times.
    void takePicture(QueuedPicture& picture, RgbImage& out, ViewFrame& frame);
    const TransferFunction& transferFunction(const ViewState& state);
    /// The slices' level of detail for `state`, and (once drawn in `seconds`) the next moving frame's.
    double sliceLodFor(const ViewState& state) const;
    void adaptMovingSliceLod(double seconds);
    void takeFinishedDetail(ViewFrame& frame);

    ViewVolume volume_;
    VoxelBox box_;
    RenderContext context_;
    std::uint64_t budget_;
    ViewQuality quality_;
    double movingSliceLod_; ///< the level of detail moving frames draw at, adapted to their time
    int movingCoarser_ = 0; ///< levels coarser moving frames draw the volume at, adapted to their time
    std::map<std::pair<std::string, double>, TransferFunction> transfers_; ///< by (preset, opacity), as made
    std::string rendererName_;
    std::vector<std::string> modes_;
    VolumeLayer opened_;
    ViewVoxelizer* voxelizer_ = nullptr;
    std::unique_ptr<DetailLayer> detail_; ///< after the context: its textures go first
    std::unique_ptr<ViewVolume> beside_;
    std::unique_ptr<BesideLayer> besideLayer_; ///< after the context: its textures go first
};

} // namespace yv
