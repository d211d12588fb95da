#include "view/view_hub.h"

#include "core/error.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>

namespace yv {

struct ViewHub::Client {
    Deliver deliver;
    ViewState wanted;
    /// A new page is drawn once it says what it wants (its size and camera follow the hello at once).
    std::uint64_t wantedVersion = 0, drawnVersion = 0;
    bool voxelizeAsked = false;
    std::optional<bool> saveAsked; ///< a save asked: through a work directory or not
    std::optional<ScreenshotMessage> screenshotAsked;
};

namespace {

Outgoing notice(const std::string& text) {
    return Outgoing{nlohmann::json{{"type", "notice"}, {"text", text}}.dump(), nullptr};
}

} // namespace

ViewHub::ViewHub(ViewControls controls, ViewState initial) : controls_(std::move(controls)), initial_(std::move(initial)) {}

std::shared_ptr<ViewHub::Client> ViewHub::join(Deliver deliver) {
    auto client = std::make_shared<Client>();
    client->deliver = std::move(deliver);
    client->wanted = initial_;
    const std::lock_guard lock(mutex_);
    clients_.push_back(client);
    wake_.notify_all();
    return client;
}

void ViewHub::leave(const std::shared_ptr<Client>& client) {
    const std::lock_guard lock(mutex_);
    clients_.erase(std::remove(clients_.begin(), clients_.end(), client), clients_.end());
}

void ViewHub::apply(Client& client, const ViewMessage& message) {
    const std::lock_guard lock(mutex_);
    ViewState next = client.wanted;
    if (const auto* c = std::get_if<CameraMessage>(&message)) {
        next.camera = c->camera;
        next.moving = c->moving;
    } else if (const auto* m = std::get_if<ModeMessage>(&message)) {
        if (std::find(controls_.modes.begin(), controls_.modes.end(), m->mode) == controls_.modes.end())
            throw Error("no mode '" + m->mode + "' in this view");
        next.mode = m->mode;
    } else if (const auto* t = std::get_if<TransferMessage>(&message)) {
        const auto& presets = controls_.transferPresets;
        if (std::find(presets.begin(), presets.end(), t->preset) == presets.end())
            throw Error("no transfer function '" + t->preset + "' in this view");
        next.transfer = t->preset;
        next.opacity = t->opacity;
    } else if (const auto* twist = std::get_if<TwistMessage>(&message)) {
        if (!controls_.twist)
            throw Error("the twist can change only where the garment is known: view the .bcc (yarnvox view GARMENT.bcc)");
        next.twist = twist->twist;
    } else if (const auto* s = std::get_if<SizeMessage>(&message)) {
        next.width = s->width;
        next.height = s->height;
    } else if (const auto* layout = std::get_if<LayoutMessage>(&message)) {
        next.blend = layout->blend;
    } else if (const auto* quality = std::get_if<QualityMessage>(&message)) {
        next.degrade = quality->degrade;
    } else if (const auto* save = std::get_if<SaveViewMessage>(&message)) {
        client.saveAsked = save->workDir;
    } else if (const auto* shot = std::get_if<ScreenshotMessage>(&message)) {
        client.screenshotAsked = *shot;
    } else {
        client.voxelizeAsked = true;
    }
    // A state already drawn is not drawn again; a changed one replaces any not yet drawn.
    if (!(next == client.wanted) || client.drawnVersion == 0) {
        client.wanted = next;
        ++client.wantedVersion;
    }
    wake_.notify_all();
}

std::shared_ptr<ViewHub::Client> ViewHub::nextDirty() {
    for (std::size_t i = 0; i < clients_.size(); ++i) {
        const std::size_t at = (turn_ + i) % clients_.size();
        const auto& c = clients_[at];
        if (c->voxelizeAsked || c->saveAsked || c->screenshotAsked || c->wantedVersion != c->drawnVersion) {
            turn_ = at + 1;
            return c;
        }
    }
    return nullptr;
}

void ViewHub::run(FrameSource& source) {
    for (;;) {
        std::shared_ptr<Client> client;
        ViewState state;
        std::uint64_t version = 0;
        bool voxelize = false;
        std::optional<bool> save;
        std::optional<ScreenshotMessage> shot;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stopped_ || (client = nextDirty()) != nullptr; });
            if (stopped_) return;
            state = client->wanted;
            version = client->wantedVersion;
            // A request is answered before the frame: the page hears of it at once.
            voxelize = client->voxelizeAsked;
            client->voxelizeAsked = false;
            if (!voxelize) save = std::exchange(client->saveAsked, std::nullopt);
            if (!voxelize && !save) shot = std::exchange(client->screenshotAsked, std::nullopt);
        }
        Outgoing out;
        const bool asked = voxelize || save || shot;
        try {
            if (voxelize) out = source.voxelizeInView(state);
            else if (save) out = source.saveView(*save);
            else if (shot) {
                ViewState large = state;
                large.width = shot->width;
                large.height = shot->height;
                out = source.screenshot(large);
            }
            else out = source.draw(state);
        } catch (const Error& e) {
            out = notice(e.what());
        }
        if (!asked) {
            const std::lock_guard lock(mutex_);
            client->drawnVersion = version; // a state that failed is not retried until it changes
        }
        client->deliver(std::move(out));
    }
}

void ViewHub::redrawAll() {
    const std::lock_guard lock(mutex_);
    for (const auto& c : clients_)
        if (c->drawnVersion != 0) ++c->wantedVersion;
    wake_.notify_all();
}

void ViewHub::broadcast(const Outgoing& message) {
    std::vector<std::shared_ptr<Client>> clients;
    {
        const std::lock_guard lock(mutex_);
        clients = clients_;
    }
    for (const auto& c : clients) c->deliver(message);
}

void ViewHub::stop() {
    const std::lock_guard lock(mutex_);
    stopped_ = true;
    wake_.notify_all();
}

} // namespace yv
