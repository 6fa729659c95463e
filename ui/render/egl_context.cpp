/// The EGL backend: the one file that includes EGL. Function pointers come from libepoxy,
/// which loads libEGL when first called; libEGL is looked for here first, because libepoxy
/// aborts the process when it cannot find it.

#include "ui/render/headless_context.h"

#include <epoxy/egl.h>

#include <dlfcn.h>

#include <string_view>
#include <vector>

namespace atelier::render {

namespace {

constexpr std::string_view INSTALL_HINT =
    "headless pictures need Mesa's EGL and OpenGL drivers (Debian: apt-get install libegl1 "
    "libegl-mesa0 libgl1-mesa-dri libopengl0)";

Error contextError(const std::string& message) {
    return Error{"", "", message + "; " + std::string(INSTALL_HINT)};
}

std::string eglErrorName(EGLint code) {
    switch (code) {
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    default:
        return "EGL error " + std::to_string(code);
    }
}

/// True when the shared library `name` can be loaded (it stays loaded, as libepoxy will use
/// it).
bool loadable(const char* name) {
    return dlopen(name, RTLD_LAZY | RTLD_GLOBAL) != nullptr;
}

/// An initialised display on `platform` for `native`, or EGL_NO_DISPLAY.
EGLDisplay initialise(EGLenum platform, void* native) {
    EGLDisplay display = eglGetPlatformDisplayEXT(platform, native, nullptr);
    if (display == EGL_NO_DISPLAY) {
        return EGL_NO_DISPLAY;
    }
    EGLint major = 0;
    EGLint minor = 0;
    if (eglInitialize(display, &major, &minor) != EGL_TRUE) {
        return EGL_NO_DISPLAY;
    }
    return display;
}

/// A display with surfaceless contexts: Mesa's surfaceless platform, else the EGL devices in
/// order. `platform` says which.
EGLDisplay openDisplay(std::string& platform) {
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base")) {
        return EGL_NO_DISPLAY;
    }
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        if (EGLDisplay d = initialise(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY);
            d != EGL_NO_DISPLAY) {
            platform = "surfaceless";
            return d;
        }
    }
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") &&
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) {
        EGLint count = 0;
        std::vector<EGLDeviceEXT> devices(16);
        if (eglQueryDevicesEXT(static_cast<EGLint>(devices.size()), devices.data(), &count) ==
            EGL_TRUE) {
            for (EGLint i = 0; i < count; ++i) {
                if (EGLDisplay d = initialise(EGL_PLATFORM_DEVICE_EXT, devices[i]);
                    d != EGL_NO_DISPLAY) {
                    platform = "device";
                    return d;
                }
            }
        }
    }
    return EGL_NO_DISPLAY;
}

} // namespace

struct HeadlessContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string platform;

    ~Impl() {
        if (display == EGL_NO_DISPLAY) {
            return;
        }
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (context != EGL_NO_CONTEXT) {
            eglDestroyContext(display, context);
        }
        eglTerminate(display);
        eglReleaseThread();
    }
};

HeadlessContext::HeadlessContext(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
HeadlessContext::~HeadlessContext() = default;

const std::string& HeadlessContext::platform() const {
    return m_impl->platform;
}

Result<std::unique_ptr<HeadlessContext>> HeadlessContext::create() {
    if (!loadable("libEGL.so.1")) {
        return contextError("cannot load libEGL.so.1");
    }
    if (!loadable("libOpenGL.so.0") && !loadable("libGL.so.1")) {
        return contextError("cannot load libOpenGL.so.0 or libGL.so.1");
    }
    auto impl = std::make_unique<Impl>();
    impl->display = openDisplay(impl->platform);
    if (impl->display == EGL_NO_DISPLAY) {
        return contextError("no EGL display: neither Mesa's surfaceless platform nor an EGL "
                            "device could be initialised");
    }
    if (!epoxy_has_egl_extension(impl->display, "EGL_KHR_surfaceless_context")) {
        return contextError("the EGL display (" + impl->platform +
                            ") cannot make a context current without a surface");
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
        return contextError("the EGL display (" + impl->platform + ") offers no desktop OpenGL");
    }
    const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (eglChooseConfig(impl->display, configAttributes, &config, 1, &configs) != EGL_TRUE ||
        configs == 0) {
        if (!epoxy_has_egl_extension(impl->display, "EGL_KHR_no_config_context")) {
            return contextError("no EGL configuration renders OpenGL");
        }
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        3,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    impl->context = eglCreateContext(impl->display, config, EGL_NO_CONTEXT, contextAttributes);
    if (impl->context == EGL_NO_CONTEXT) {
        return contextError("no OpenGL 3.3 core context on the EGL display (" + impl->platform +
                            "): " + eglErrorName(eglGetError()));
    }
    if (eglMakeCurrent(impl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl->context) != EGL_TRUE) {
        return contextError("cannot make the OpenGL context current: " +
                            eglErrorName(eglGetError()));
    }
    return std::unique_ptr<HeadlessContext>(new HeadlessContext(std::move(impl)));
}

} // namespace atelier::render
