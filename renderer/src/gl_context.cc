#include "hcpf/renderer/gl_context.h"

// EGL and OSMesa headers only here; GL calls go through GlApi (gl_api.h).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <dlfcn.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <type_traits>
#include <vector>

#include "gl_api.h"
#include "hcpf/core/error.h"
#include "logging.h"

namespace hcpf::renderer {

namespace internal {

std::string GlApi::Load(ProcLoader loader) {
#define HCPF_GL_LOAD(type, member, name)         \
  member = reinterpret_cast<type>(loader(name)); \
  if (member == nullptr) return name;
  HCPF_GL_FUNCTIONS(HCPF_GL_LOAD)
#undef HCPF_GL_LOAD
  return {};
}

void GlApi::CheckError(const char* where) const {
  const GLenum error = GetError();
  if (error != GL_NO_ERROR) {
    throw RunError(fmt::format("OpenGL error 0x{:04x} in {}", error, where));
  }
}

}  // namespace internal

std::string_view ToString(GlBackend backend) {
  switch (backend) {
    case GlBackend::kAuto:
      return "auto";
    case GlBackend::kOsMesa:
      return "osmesa";
    case GlBackend::kEgl:
      return "egl";
  }
  return "?";
}

GlBackend ParseGlBackend(std::string_view text) {
  if (text == "auto") return GlBackend::kAuto;
  if (text == "osmesa") return GlBackend::kOsMesa;
  if (text == "egl") return GlBackend::kEgl;
  throw InputError(SourceLocation{.key = "renderer.backend"}, "one of auto, osmesa, egl",
                   fmt::format("\"{}\"", text));
}

GlContext::GlContext() = default;

void GlContext::CheckNoError(const char* where) const { api_->CheckError(where); }
GlContext::~GlContext() = default;

void GlContext::Initialise(const std::string& backend, void* (*loader)(const char*),
                           const std::string& platform) {
  api_ = std::make_unique<internal::GlApi>();
  const std::string missing = api_->Load(loader);
  if (!missing.empty()) {
    throw InputError(fmt::format("{}: GL entry point {} not available", backend, missing));
  }
  const auto str = [&](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(api_->GetString(name));
    return std::string(s != nullptr ? s : "");
  };
  info_.backend = backend;
  info_.platform = platform;
  info_.vendor = str(GL_VENDOR);
  info_.renderer = str(GL_RENDERER);
  info_.version = str(GL_VERSION);
  info_.softpipe = info_.renderer.find("softpipe") != std::string::npos;
  Logger()->info("GL context ({}): vendor \"{}\", renderer \"{}\", version \"{}\"", platform,
                 info_.vendor, info_.renderer, info_.version);
  if (info_.softpipe) {
    Logger()->warn(
        "GL driver is SOFTPIPE: rendering will be about 20x slower than llvmpipe. "
        "Unset GALLIUM_DRIVER or set GALLIUM_DRIVER=llvmpipe.");
  }
  GLint major = 0;
  GLint minor = 0;
  api_->GetIntegerv(GL_MAJOR_VERSION, &major);
  api_->GetIntegerv(GL_MINOR_VERSION, &minor);
  GLint profile = 0;
  api_->GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  info_.core_profile = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  if (major * 10 + minor < 33) {
    throw InputError(
        fmt::format("{}: OpenGL {}.{} context, need at least 3.3 core", backend, major, minor));
  }
}

namespace {

// ---------------------------------------------------------------------------
// OSMesa

// libOSMesa is opened on first use rather than linked: it pulls in LLVM,
// whose start-up costs every hcpf process ~20 ms even when nothing renders
// (e.g. `hcpf score`).
struct OsMesaLibrary {
  decltype(&OSMesaCreateContextAttribs) create_context_attribs = nullptr;
  decltype(&OSMesaMakeCurrent) make_current = nullptr;
  decltype(&OSMesaDestroyContext) destroy_context = nullptr;
  decltype(&OSMesaGetProcAddress) get_proc_address = nullptr;
};

const OsMesaLibrary& OsMesa() {
  static const OsMesaLibrary library = [] {
    OsMesaLibrary l;
    void* handle = ::dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      throw InputError(fmt::format("cannot load libOSMesa.so.8 ({})", ::dlerror()));
    }
    const auto load = [handle](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(::dlsym(handle, name));
      if (fn == nullptr) throw InputError(fmt::format("libOSMesa.so.8 lacks {}", name));
    };
    load(l.create_context_attribs, "OSMesaCreateContextAttribs");
    load(l.make_current, "OSMesaMakeCurrent");
    load(l.destroy_context, "OSMesaDestroyContext");
    load(l.get_proc_address, "OSMesaGetProcAddress");
    return l;
  }();
  return library;
}

void* OsMesaLoader(const char* name) {
  return reinterpret_cast<void*>(OsMesa().get_proc_address(name));
}

class OsMesaContext final : public GlContext {
 public:
  OsMesaContext() {
    // Ask for 4.5 core; llvmpipe on Mesa 22.3 gives it. 3.3 core is enough
    // for our shaders, so fall back to it.
    for (int minor_version : {5, 3}) {
      const int major_version = minor_version == 5 ? 4 : 3;
      const int attribs[] = {OSMESA_FORMAT,
                             OSMESA_RGBA,
                             OSMESA_DEPTH_BITS,
                             0,
                             OSMESA_STENCIL_BITS,
                             0,
                             OSMESA_PROFILE,
                             OSMESA_CORE_PROFILE,
                             OSMESA_CONTEXT_MAJOR_VERSION,
                             major_version,
                             OSMESA_CONTEXT_MINOR_VERSION,
                             minor_version,
                             0};
      context_ = OsMesa().create_context_attribs(attribs, nullptr);
      if (context_ != nullptr) break;
    }
    if (context_ == nullptr)
      throw InputError("OSMesaCreateContextAttribs failed (no core profile)");
    MakeCurrent();
    Initialise("osmesa", &OsMesaLoader, "osmesa");
  }
  ~OsMesaContext() override {
    if (context_ != nullptr) OsMesa().destroy_context(context_);
  }
  void MakeCurrent() override {
    // OSMesa needs a colour buffer to make a context current; ours is a
    // dummy, all rendering goes to framebuffer objects.
    if (OsMesa().make_current(context_, dummy_, GL_UNSIGNED_BYTE, kDummySize, kDummySize) == 0) {
      throw InputError("OSMesaMakeCurrent failed");
    }
  }

 private:
  static constexpr int kDummySize = 4;
  OSMesaContext context_ = nullptr;
  unsigned char dummy_[kDummySize * kDummySize * 4] = {};
};

// ---------------------------------------------------------------------------
// EGL

void* EglLoader(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplay() {
  auto fn = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (fn == nullptr) throw InputError("EGL: no eglGetPlatformDisplayEXT");
  return fn;
}

// The devices eglQueryDevicesEXT lists (at most 16), empty without the
// extension.
std::vector<EGLDeviceEXT> EglDevices() {
  auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (query_devices == nullptr) return {};
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (query_devices(16, devices, &count) != EGL_TRUE || count < 0) return {};
  return std::vector<EGLDeviceEXT>(devices, devices + std::min<EGLint>(count, 16));
}

class EglContext final : public GlContext {
 public:
  explicit EglContext(const GlAttempt& attempt) {
    try {
      Open(attempt);
    } catch (...) {
      Release();  // a failed attempt leaves no display behind for the next
      throw;
    }
  }
  ~EglContext() override { Release(); }
  void MakeCurrent() override {
    if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
      throw InputError(fmt::format("EGL: eglMakeCurrent failed (error 0x{:x})", eglGetError()));
    }
  }

  static std::string DeviceExtensions(EGLDeviceEXT device) {
    auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
        eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (query_string == nullptr) return {};
    const char* text = query_string(device, EGL_EXTENSIONS);
    return text != nullptr ? std::string(text) : std::string();
  }

 private:
  void Open(const GlAttempt& attempt) {
    const PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = GetPlatformDisplay();
    std::string platform;
    if (attempt.kind == GlAttempt::Kind::kEglSurfaceless) {
      display_ = TryInitialise(
          get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
      if (display_ == EGL_NO_DISPLAY) {
        throw InputError(
            fmt::format("EGL: surfaceless platform failed (error 0x{:x})", eglGetError()));
      }
      platform = "egl surfaceless";
    } else {
      const std::vector<EGLDeviceEXT> devices = EglDevices();
      if (attempt.device < 0 || static_cast<size_t>(attempt.device) >= devices.size()) {
        throw InputError(fmt::format("EGL: no device {}", attempt.device));
      }
      EGLDeviceEXT device = devices[static_cast<size_t>(attempt.device)];
      display_ = TryInitialise(get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr));
      if (display_ == EGL_NO_DISPLAY) {
        throw InputError(
            fmt::format("EGL: device {} failed (error 0x{:x})", attempt.device, eglGetError()));
      }
      const bool software = EglDeviceDescription{.extensions = DeviceExtensions(device)}.software();
      platform =
          fmt::format("egl device {} ({})", attempt.device, software ? "software" : "hardware");
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) throw InputError("EGL: eglBindAPI(OpenGL) failed");
    for (int minor_version : {5, 3}) {
      const EGLint major_version = minor_version == 5 ? 4 : 3;
      const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                major_version,
                                EGL_CONTEXT_MINOR_VERSION,
                                minor_version,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                EGL_NONE};
      // EGL_KHR_no_config_context: a context for FBO rendering needs no config.
      context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
      if (context_ != EGL_NO_CONTEXT) break;
    }
    if (context_ == EGL_NO_CONTEXT) {
      throw InputError(fmt::format("EGL: eglCreateContext failed (error 0x{:x})", eglGetError()));
    }
    MakeCurrent();
    Initialise("egl", &EglLoader, platform);
  }
  void Release() {
    if (display_ != EGL_NO_DISPLAY) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
      eglTerminate(display_);
      display_ = EGL_NO_DISPLAY;
      context_ = EGL_NO_CONTEXT;
    }
  }
  static EGLDisplay TryInitialise(EGLDisplay display) {
    if (display == EGL_NO_DISPLAY) return EGL_NO_DISPLAY;
    EGLint major = 0;
    EGLint minor = 0;
    return eglInitialize(display, &major, &minor) == EGL_TRUE ? display : EGL_NO_DISPLAY;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

std::string Describe(const GlAttempt& attempt) {
  switch (attempt.kind) {
    case GlAttempt::Kind::kOsMesa:
      return "osmesa";
    case GlAttempt::Kind::kEglSurfaceless:
      return "egl surfaceless";
    case GlAttempt::Kind::kEglDevice:
      return fmt::format("egl device {}", attempt.device);
  }
  return "?";
}

}  // namespace

bool EglDeviceDescription::software() const {
  return extensions.find("EGL_MESA_device_software") != std::string::npos;
}

std::vector<GlAttempt> PlanGlAttempts(GlBackend backend,
                                      std::span<const EglDeviceDescription> devices) {
  using Kind = GlAttempt::Kind;
  std::vector<GlAttempt> plan;
  if (backend == GlBackend::kOsMesa) return {GlAttempt{.kind = Kind::kOsMesa}};
  for (const EglDeviceDescription& d : devices) {
    if (!d.software()) plan.push_back({.kind = Kind::kEglDevice, .device = d.index});
  }
  if (backend == GlBackend::kAuto) plan.push_back({.kind = Kind::kOsMesa});
  plan.push_back({.kind = Kind::kEglSurfaceless});
  for (const EglDeviceDescription& d : devices) {
    if (d.software()) plan.push_back({.kind = Kind::kEglDevice, .device = d.index});
  }
  return plan;
}

std::vector<EglDeviceDescription> QueryEglDevices() {
  std::vector<EglDeviceDescription> out;
  const std::vector<EGLDeviceEXT> devices = EglDevices();
  for (size_t i = 0; i < devices.size(); ++i) {
    out.push_back(
        {.index = static_cast<int>(i), .extensions = EglContext::DeviceExtensions(devices[i])});
  }
  return out;
}

std::unique_ptr<GlContext> GlContext::Create(GlBackend backend) {
  // Before the first context: llvmpipe reads LP_NUM_THREADS once, when its
  // screen is made (the header says why 0). Once, so that no later call
  // writes the environment while another thread may read it.
  static std::once_flag rasterise_on_the_calling_thread;
  std::call_once(rasterise_on_the_calling_thread,
                 [] { ::setenv("LP_NUM_THREADS", "0", /*overwrite=*/0); });
  // Enumerating EGL devices loads the EGL vendor libraries; OSMesa alone
  // needs none of that.
  const std::vector<EglDeviceDescription> devices =
      backend == GlBackend::kOsMesa ? std::vector<EglDeviceDescription>{} : QueryEglDevices();
  std::string failures;
  for (const GlAttempt& attempt : PlanGlAttempts(backend, devices)) {
    try {
      if (attempt.kind == GlAttempt::Kind::kOsMesa) return std::make_unique<OsMesaContext>();
      return std::make_unique<EglContext>(attempt);
    } catch (const Error& e) {
      failures += fmt::format("{}: {}; ", Describe(attempt), e.what());
      Logger()->debug("GL backend {} failed: {}", Describe(attempt), e.what());
    }
  }
  throw InputError(fmt::format(
      "renderer.backend {}: no OpenGL 3.3+ core context could be created ({}). Install Mesa's "
      "OSMesa or EGL (llvmpipe needs no GPU), or choose another backend.",
      ToString(backend), failures));
}

}  // namespace hcpf::renderer
