#include "gpu/egl_context.h"

#include "core/error.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <dlfcn.h>

#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

namespace yv {
namespace {

constexpr const char* kNoContext = "no OpenGL 4.5 context: ";

[[noreturn]] void fail(const std::string& what) { throw Error(kNoContext + what); }

/// Whole-token match in a space-separated extension list (null-safe).
bool hasToken(const char* list, std::string_view name) {
    if (!list) return false;
    std::string_view s(list);
    for (size_t pos = 0; (pos = s.find(name, pos)) != std::string_view::npos; pos += name.size()) {
        const bool startOk = pos == 0 || s[pos - 1] == ' ';
        const size_t end = pos + name.size();
        if (startOk && (end == s.size() || s[end] == ' ')) return true;
    }
    return false;
}

std::string eglErrorName(EGLint e) {
    switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: {
        std::ostringstream os;
        os << "EGL error 0x" << std::hex << e;
        return os.str();
    }
    }
}

// libepoxy dlopens libEGL and libOpenGL/libGL on first use and abort()s when
// they are missing; checking first turns that into an Error (and lets
// available() answer false instead of killing the process).
void requireLibraries() {
    auto present = [](const char* lib) {
        void* h = dlopen(lib, RTLD_LAZY | RTLD_LOCAL);
        if (h) dlclose(h);
        return h != nullptr;
    };
    if (!present("libEGL.so.1"))
        fail("libEGL.so.1 not found (install libegl1 and libegl-mesa0, or use --backend cpu)");
    if (!present("libOpenGL.so.0") && !present("libGL.so.1"))
        fail("libOpenGL.so.0 not found (install libopengl0 and libgl1-mesa-dri, or use --backend cpu)");
}

// EGL displays are per-process singletons and eglTerminate destroys every
// context on one, so live GlContexts share a display through a use count.
std::mutex gDisplayMutex;
std::map<EGLDisplay, int> gDisplayUsers;
// Live contexts in creation order, so destroying an inner one hands the thread
// back to the one made before it (RAII nesting keeps working).
std::mutex gStackMutex;
std::vector<std::pair<EGLDisplay, EGLContext>> gContextStack;

bool acquireDisplay(EGLDisplay d, EGLint* major, EGLint* minor) {
    std::lock_guard lock(gDisplayMutex);
    if (!eglInitialize(d, major, minor)) return false;
    ++gDisplayUsers[d];
    return true;
}

void releaseDisplay(EGLDisplay d) {
    std::lock_guard lock(gDisplayMutex);
    auto it = gDisplayUsers.find(d);
    if (it == gDisplayUsers.end()) return;
    if (--it->second == 0) {
        gDisplayUsers.erase(it);
        eglTerminate(d);
    }
}

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei,
                              const GLchar* message, const void*) {
    if (severity != GL_DEBUG_SEVERITY_HIGH && severity != GL_DEBUG_SEVERITY_MEDIUM) return;
    std::fprintf(stderr, "GL debug [%s, source 0x%x, type 0x%x, id %u]: %s\n",
                 severity == GL_DEBUG_SEVERITY_HIGH ? "high" : "medium", source, type, id, message);
}

long long readFreeMemory() {
    if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
        GLint kib = 0;
        glGetIntegerv(GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX, &kib);
        return static_cast<long long>(kib) * 1024;
    }
    if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
        GLint v[4] = {0, 0, 0, 0}; // [0] is the total free pool in KiB
        glGetIntegerv(GL_TEXTURE_FREE_MEMORY_ATI, v);
        return static_cast<long long>(v[0]) * 1024;
    }
    return -1;
}

std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

} // namespace

struct GlContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY; // set only once acquired
    EGLContext context = EGL_NO_CONTEXT;
    /// What the context was made with, so that a sharing one is made alike.
    EGLConfig config = EGL_NO_CONFIG_KHR;
    std::vector<EGLint> attribs;
    GlInfo info;

    ~Impl() {
        if (context != EGL_NO_CONTEXT) {
            std::pair<EGLDisplay, EGLContext> previous{EGL_NO_DISPLAY, EGL_NO_CONTEXT};
            {
                std::lock_guard lock(gStackMutex);
                // A sharing context, made for another thread, is not on the
                // stack: destroyed, it leaves its thread with none.
                const bool nested = std::erase(gContextStack, std::pair{display, context}) > 0;
                if (nested && !gContextStack.empty()) previous = gContextStack.back();
            }
            if (eglGetCurrentContext() == context) {
                eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
                if (previous.second != EGL_NO_CONTEXT)
                    eglMakeCurrent(previous.first, EGL_NO_SURFACE, EGL_NO_SURFACE, previous.second);
            }
            eglDestroyContext(display, context);
        }
        if (display != EGL_NO_DISPLAY) releaseDisplay(display);
    }

    /// Creates the 4.5 core context on the already acquired `display` and
    /// makes it current; `where` names the display in error messages.
    void createContext(const std::string& where, EGLint eglMajor, EGLint eglMinor, bool debug);
};

void GlContext::Impl::createContext(const std::string& where, EGLint eglMajor, EGLint eglMinor,
                                    bool debug) {
    const std::string driverHint = "update Mesa or the GPU driver, or use --backend cpu";
    if (!eglBindAPI(EGL_OPENGL_API)) {
        const char* apis = eglQueryString(display, EGL_CLIENT_APIS);
        fail(where + " offers no desktop OpenGL (EGL_CLIENT_APIS: " + (apis ? apis : "?") +
             "; install libgl1-mesa-dri or the GPU's full GL driver, or use --backend cpu)");
    }

    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    std::vector<EGLint> attribs = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
    if (debug) {
        // EGL_CONTEXT_OPENGL_DEBUG is 1.5-only; 1.4 drivers take the KHR flag.
        if (eglMajor > 1 || eglMinor >= 5)
            attribs.insert(attribs.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
        else
            attribs.insert(attribs.end(), {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
    }
    attribs.push_back(EGL_NONE);

    // No surface is ever drawn to, so no config is needed where the driver
    // allows that; otherwise any GL-renderable config will do (pbuffer ones
    // first, as surfaceless drivers may list only those). Caveats such as
    // EGL_SLOW_CONFIG on software configs are irrelevant here.
    std::vector<EGLConfig> configs;
    if (hasToken(ext, "EGL_KHR_no_config_context") || hasToken(ext, "EGL_MESA_configless_context"))
        configs.push_back(EGL_NO_CONFIG_KHR);
    for (EGLint surfaceType : {EGLint(EGL_PBUFFER_BIT), EGLint(0)}) {
        const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, surfaceType,
                               EGL_CONFIG_CAVEAT, EGL_DONT_CARE, EGL_NONE};
        EGLConfig cfg = nullptr;
        EGLint n = 0;
        if (eglChooseConfig(display, want, &cfg, 1, &n) && n > 0) configs.push_back(cfg);
    }
    if (configs.empty())
        fail(where + " has no OpenGL-renderable EGL config (" + driverHint + ")");

    EGLint lastError = EGL_SUCCESS;
    for (EGLConfig cfg : configs) {
        context = eglCreateContext(display, cfg, EGL_NO_CONTEXT, attribs.data());
        if (context != EGL_NO_CONTEXT) {
            config = cfg;
            break;
        }
        lastError = eglGetError();
    }
    this->attribs = attribs;
    if (context == EGL_NO_CONTEXT)
        fail("eglCreateContext for OpenGL 4.5 core failed on " + where + " (" +
             eglErrorName(lastError) + "; " + driverHint + ")");

    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
        fail("cannot make a context current without a surface on " + where + " (" +
             eglErrorName(eglGetError()) + (hasToken(ext, "EGL_KHR_surfaceless_context")
                                                ? ""
                                                : "; EGL_KHR_surfaceless_context missing") +
             "; " + driverHint + ")");

    GLint major = 0, minor = 0, profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    info.vendor = glString(GL_VENDOR);
    info.renderer = glString(GL_RENDERER);
    info.version = glString(GL_VERSION);
    if (major * 10 + minor < 45 || !(profile & GL_CONTEXT_CORE_PROFILE_BIT))
        fail("driver gives OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
             ((profile & GL_CONTEXT_CORE_PROFILE_BIT) ? " core" : " (not core)") + " on " +
             info.renderer + ", need 4.5 core (" + driverHint + ")");

    if (debug) {
        glEnable(GL_DEBUG_OUTPUT);
        // Synchronous so a message arrives inside the call that caused it.
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_LOW, 0, nullptr, GL_FALSE);
        glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr,
                              GL_FALSE);
        glDebugMessageCallback(debugCallback, nullptr);
    }

    GLint64 ssbo = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssbo);
    info.maxSsboBlockSize = ssbo;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &info.maxComputeWorkGroupCountX);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &info.maxTextureSize);
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info.max3dTextureSize);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, info.maxViewportDims);
    info.freeMemoryBytes = readFreeMemory();
    info.hasConservativeRaster = epoxy_has_gl_extension("GL_NV_conservative_raster");
}

GlContext::GlContext(const GlContextOptions& options) : impl_(std::make_unique<Impl>()) {
    requireLibraries();
    Impl& m = *impl_;
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!hasToken(client, "EGL_EXT_platform_base"))
        fail("EGL has no usable vendor library (EGL_EXT_platform_base missing; install libegl-mesa0 "
             "and libgl1-mesa-dri, or use --backend cpu)");

    const bool canEnumerate = (hasToken(client, "EGL_EXT_device_enumeration") ||
                               hasToken(client, "EGL_EXT_device_base")) &&
                              hasToken(client, "EGL_EXT_platform_device");
    const bool canQuery = hasToken(client, "EGL_EXT_device_query") ||
                          hasToken(client, "EGL_EXT_device_base");
    std::vector<EGLDeviceEXT> hardware;
    EGLint listed = 0;
    if (canEnumerate && eglQueryDevicesEXT(0, nullptr, &listed) && listed > 0) {
        std::vector<EGLDeviceEXT> all(static_cast<size_t>(listed));
        eglQueryDevicesEXT(listed, all.data(), &listed);
        all.resize(static_cast<size_t>(listed));
        for (EGLDeviceEXT dev : all) {
            const char* devExt = canQuery ? eglQueryDeviceStringEXT(dev, EGL_EXTENSIONS) : nullptr;
            if (!hasToken(devExt, "EGL_MESA_device_software")) hardware.push_back(dev);
        }
    }

    EGLint eglMajor = 0, eglMinor = 0;
    if (options.device >= 0 || !hardware.empty()) {
        if (options.device >= 0 && !canEnumerate)
            fail("EGL device " + std::to_string(options.device) +
                 " requested but EGL cannot list devices (EGL_EXT_device_enumeration and "
                 "EGL_EXT_platform_device missing; install libegl1 from libglvnd and the GPU's EGL "
                 "driver, or use --backend cpu)");
        // Usable means the display initialises: Mesa also lists DRM nodes of
        // GPUs it has no driver for (e.g. NVIDIA's), and those fail here.
        int wanted = options.device >= 0 ? options.device : options.spreadIndex;
        int usable = 0;
        std::string where;
        const auto take = [&] {
            usable = 0;
            for (size_t i = 0; i < hardware.size() && m.display == EGL_NO_DISPLAY; ++i) {
                EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, hardware[i], nullptr);
                if (d == EGL_NO_DISPLAY || !acquireDisplay(d, &eglMajor, &eglMinor)) continue;
                if (usable++ != wanted) {
                    releaseDisplay(d);
                    continue;
                }
                m.display = d;
                where = "EGL device " + std::to_string(wanted);
                const char* devExt = canQuery ? eglQueryDeviceStringEXT(hardware[i], EGL_EXTENSIONS) : nullptr;
                if (hasToken(devExt, "EGL_EXT_device_drm"))
                    if (const char* node = eglQueryDeviceStringEXT(hardware[i], EGL_DRM_DEVICE_FILE_EXT))
                        where += std::string(" (") + node + ")";
            }
        };
        take();
        // Spread over fewer GPUs than processes: wrap around.
        if (m.display == EGL_NO_DISPLAY && options.device < 0 && usable > 0) {
            wanted %= usable;
            take();
        }
        if (m.display != EGL_NO_DISPLAY) {
            m.info.platform = GlPlatform::Device;
            m.createContext(where, eglMajor, eglMinor, options.debug);
        } else if (options.device >= 0) {
            if (usable == 0)
                fail("EGL device " + std::to_string(options.device) + " requested but no usable "
                     "hardware EGL device found (" + std::to_string(listed) + " listed; install the "
                     "GPU's EGL driver, e.g. the NVIDIA driver's libEGL_nvidia, request no device for "
                     "the software renderer, or use --backend cpu)");
            fail("EGL device " + std::to_string(options.device) + " requested but only " +
                 std::to_string(usable) + " usable hardware EGL device(s) exist (pick 0.." +
                 std::to_string(usable - 1) + ", or use --backend cpu)");
        }
        // Auto mode with no device that initialises: fall through to software.
    }

    if (m.display == EGL_NO_DISPLAY) {
        if (!hasToken(client, "EGL_MESA_platform_surfaceless"))
            fail("EGL surfaceless platform unavailable (install libegl-mesa0 and libgl1-mesa-dri, "
                 "or use --backend cpu)");
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d == EGL_NO_DISPLAY || !acquireDisplay(d, &eglMajor, &eglMinor))
            fail("EGL surfaceless platform failed to initialise (" + eglErrorName(eglGetError()) +
                 "; install libgl1-mesa-dri, or use --backend cpu)");
        m.display = d;
        m.info.platform = GlPlatform::Surfaceless;
        m.createContext("the EGL surfaceless platform", eglMajor, eglMinor, options.debug);
    }
    std::lock_guard lock(gStackMutex);
    gContextStack.emplace_back(m.display, m.context);
}

GlContext::GlContext(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

std::unique_ptr<GlContext> GlContext::makeSharing() const {
    auto impl = std::make_unique<Impl>();
    EGLint major = 0, minor = 0;
    if (!acquireDisplay(impl_->display, &major, &minor))
        fail("cannot make a second GL context: the display does not initialise again (" + eglErrorName(eglGetError()) + ")");
    impl->display = impl_->display;
    impl->config = impl_->config;
    impl->attribs = impl_->attribs;
    impl->info = impl_->info;
    if (!eglBindAPI(EGL_OPENGL_API)) fail("cannot make a second GL context: eglBindAPI failed");
    impl->context = eglCreateContext(impl->display, impl->config, impl_->context, impl->attribs.data());
    if (impl->context == EGL_NO_CONTEXT)
        fail("cannot make a GL context sharing the first (" + eglErrorName(eglGetError()) + ")");
    if (!eglMakeCurrent(impl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl->context))
        fail("cannot make the sharing GL context current (" + eglErrorName(eglGetError()) + ")");
    return std::unique_ptr<GlContext>(new GlContext(std::move(impl)));
}

GlContext::~GlContext() = default;

const GlInfo& GlContext::info() const { return impl_->info; }

long long GlContext::queryFreeMemoryBytes() const {
    // The query reads whichever context is current; make sure it is ours.
    if (eglGetCurrentContext() != impl_->context)
        eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context);
    return readFreeMemory();
}

void GlContext::makeCurrent() const {
    if (eglGetCurrentContext() != impl_->context && !eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
        fail("cannot make the GL context current on this thread (" + eglErrorName(eglGetError()) + ")");
}

void GlContext::releaseCurrent() const {
    if (eglGetCurrentContext() == impl_->context) eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

bool GlContext::available() {
    static std::mutex mutex;
    static std::optional<bool> cached;
    std::lock_guard lock(mutex);
    if (cached) return *cached;
    // A probe would steal the current context from a live one; one existing
    // already answers the question.
    {
        std::lock_guard stackLock(gStackMutex);
        if (!gContextStack.empty()) return *(cached = true);
    }
    try {
        GlContext probe;
        cached = true;
    } catch (...) {
        cached = false;
    }
    return *cached;
}

} // namespace yv
