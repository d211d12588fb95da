// What a page of `yarnvox view` may say to the server: JSON text messages
// over the WebSocket, parsed and checked here before anything acts on them.
// Every field is bounded (a message's size, numbers finite and within
// range, strings short and of known characters, no unknown type or field),
// so a malformed or hostile message is refused with one line and nothing
// else happens. No GL and no network here: the fuzz target links this alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace yv {

/// The largest client message accepted, in bytes (a camera message is about 120).
constexpr std::size_t kMaxViewMessageBytes = 1024;
/// The frame size limits, pixels a side (the upper one: the 4096 screenshot).
constexpr int kMinViewSide = 16, kMaxViewSide = 4096;

/// Where the camera is: the angles of inspect's --view (degrees, degrees,
/// bounding-sphere radii) and a pan of the point looked at, in sphere radii
/// along the picture's right and up.
struct ViewCamera {
    double azimuth = 30.0, elevation = 20.0, distance = 4.0;
    double panX = 0.0, panY = 0.0;
    /// The page's number for this camera state, echoed in the stats of the
    /// frame that shows it, so the page can time input to picture.
    std::uint64_t seq = 0;
    bool operator==(const ViewCamera&) const = default;
};

/// {"type":"camera","azimuth":A,"elevation":E,"distance":D,"panX":X,"panY":Y,"seq":N,"moving":true}
/// ("moving" may be left out: false). The page says moving while input goes
/// on and sends the camera once more, not moving, when it stops.
struct CameraMessage {
    ViewCamera camera;
    bool moving = false;
};
/// {"type":"mode","mode":"raycast"}: which render; the scene says whether it has it.
struct ModeMessage {
    std::string mode;
};
/// {"type":"size","width":W,"height":H}: the frame's size in pixels.
struct SizeMessage {
    int width = 0, height = 0;
};
/// {"type":"voxelize-view"}: voxelize what the camera of the page's latest
/// state sees (the page sends it when the camera stops).
struct VoxelizeViewMessage {};
/// {"type":"save-view","workDir":false}: save the view's voxelization shown
/// last, as its .vdb or (workDir) through a work directory.
struct SaveViewMessage {
    bool workDir = false;
};

/// {"type":"layout","blend":true}: a garment's view as one picture, the ray
/// cast blended over the slices (the paper's Figure 3), or (false) beside them.
struct LayoutMessage {
    bool blend = false;
};
/// {"type":"quality","degrade":false}: whether frames drawn while the
/// camera moves may draw fewer slices when they would be late (true, the
/// default), or every frame is drawn at full quality (false).
struct QualityMessage {
    bool degrade = true;
};
/// {"type":"screenshot","width":W,"height":H}: one picture of the page's
/// view at this size (up to 4096 a side, larger than any window), sent once.
struct ScreenshotMessage {
    int width = 0, height = 0;
};

/// {"type":"transfer","preset":"heat","opacity":1.5}: the ray cast's
/// transfer function, a preset by name (the scene says which it has) with
/// its opacity scaled (withOpacityScale's factor).
struct TransferMessage {
    std::string preset;
    double opacity = 1.0;
};
/// The largest yarn twist a page may set, radians per world unit either way.
constexpr double kMaxViewTwist = 1.0e4;
/// {"type":"twist","twist":T}: the yarn twist, radians per world unit, the
/// slices are shaded with and what the camera sees is voxelized with.
struct TwistMessage {
    double twist = 0.0;
};

using ViewMessage =
    std::variant<CameraMessage, ModeMessage, SizeMessage, VoxelizeViewMessage, SaveViewMessage, ScreenshotMessage,
                 LayoutMessage, TransferMessage, TwistMessage, QualityMessage>;

/// Parses one text message. Throws yv::Error with one line saying what is
/// wrong (too long, not JSON, not an object, an unknown type or field, a
/// field missing, of the wrong kind, not finite or out of range).
ViewMessage parseViewMessage(std::string_view text);

/// The message as JSON text again (what parseViewMessage reads back to the same message).
std::string formatViewMessage(const ViewMessage& message);

} // namespace yv
