// Between the pages and the render thread of `yarnvox view`: each page's
// wanted view state, and the loop that draws them. Camera messages are
// coalesced (a page's state is overwritten; only the latest is drawn), pages
// are served in turn, and a frame goes to its page's delivery function,
// which keeps only the newest undelivered one. GL-free: the drawing is a
// FrameSource, so the loop is tested without a context.
#pragma once

#include "view/view_message.h"
#include "view/view_scene.h"

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace yv {

/// What goes to a page: a text message and, for a frame, the JPEG after it.
struct Outgoing {
    std::string text;
    std::shared_ptr<const std::vector<std::uint8_t>> jpeg; ///< null for a text message alone
    bool keep = false; ///< a picture asked for once (a screenshot): never replaced by a newer frame
};

/// Draws frames for the loop (the render thread's side).
class FrameSource {
  public:
    virtual ~FrameSource() = default;
    /// The stats text and the JPEG of `state`; throws yv::Error.
    virtual Outgoing draw(const ViewState& state) = 0;
    /// Voxelize what `state`'s camera sees (ViewScene::voxelizeInView): the
    /// answer for the page that asked; throws yv::Error.
    virtual Outgoing voxelizeInView(const ViewState& state) = 0;
    /// Save the view voxelization shown (ViewScene::saveView): the answer; throws yv::Error.
    virtual Outgoing saveView(bool workDir) = 0;
    /// One picture of `state` (its size the screenshot's), kept until sent; throws yv::Error.
    virtual Outgoing screenshot(const ViewState& state) = 0;
};

/// What pages may change beside the camera, size and layout.
struct ViewControls {
    std::vector<std::string> modes;           ///< the modes pages may ask for
    std::vector<std::string> transferPresets; ///< the transfer functions, by name
    bool twist = false;                       ///< whether the twist may change (ViewScene::twistable)
};

class ViewHub {
  public:
    using Deliver = std::function<void(Outgoing)>;
    struct Client;

    /// `initial`: a new page's state.
    ViewHub(ViewControls controls, ViewState initial);

    /// A new page, whose frames go to `deliver` (called on the render thread).
    std::shared_ptr<Client> join(Deliver deliver);
    void leave(const std::shared_ptr<Client>& client);
    /// Applies a parsed message to `client`'s wanted state. Throws yv::Error
    /// for a mode or transfer function this view does not have, or a twist
    /// it cannot change.
    void apply(Client& client, const ViewMessage& message);

    /// Draws what pages want until stop(): each page's latest state, once.
    void run(FrameSource& source);
    /// Every page's state drawn again (what the frames show has changed). Any thread.
    void redrawAll();
    /// `message` to every page. Any thread.
    void broadcast(const Outgoing& message);
    void stop();

  private:
    std::shared_ptr<Client> nextDirty(); ///< with mutex_ held
    ViewControls controls_;
    ViewState initial_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<std::shared_ptr<Client>> clients_;
    std::size_t turn_ = 0;
    bool stopped_ = false;
};

} // namespace yv
