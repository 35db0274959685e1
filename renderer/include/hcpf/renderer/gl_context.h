#pragma once
// An off-screen OpenGL 4.5 (or at least 3.3) core-profile context, from one of
// two backends:
//   kOsMesa: OSMesaCreateContextAttribs (Mesa's off-screen library; Debian 12
//            ships it, Mesa >= 25.1 no longer does);
//   kEgl:    EGL without a surface: a hardware EGL device (EGL_EXT_device_base,
//            platform EGL_PLATFORM_DEVICE_EXT), then the surfaceless platform
//            (EGL_MESA_platform_surfaceless), then software EGL devices;
//   kAuto:   a hardware EGL device (a GPU), then OSMesa, then EGL surfaceless,
//            then software EGL devices — so a machine with a GPU renders on it
//            without being asked (PlanGlAttempts holds the order).
// A device is software when its extension string names
// EGL_MESA_device_software (Mesa's llvmpipe device); every other device
// (NVIDIA's, a DRM render node's) counts as hardware.
// All drawing goes to the renderer's own framebuffer objects, so the context
// needs no window or default framebuffer. Creating a context logs GL_VENDOR,
// GL_RENDERER and GL_VERSION (spdlog logger "renderer") and warns loudly on
// softpipe, which is about 20x slower than llvmpipe.
//
// One context per thread: MakeCurrent() binds it to the calling thread.
//
// llvmpipe (Mesa's software rasteriser, behind OSMesa and software EGL)
// rasterises on the thread that draws: the first Create of a process sets
// LP_NUM_THREADS=0 unless the environment sets it. With rasteriser threads,
// Mesa 22.3.6 frees a scene's fence after reading it signalled without its
// lock while the rasteriser thread that signalled it still holds that lock
// (ThreadSanitizer reports it in every `hcpf run` on a busy machine; a sweep
// crashed once inside libOSMesa), docs/renderer.md. LP_NUM_THREADS=N asks
// for N threads anyway; a GPU's driver ignores the variable.

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hcpf::renderer {

namespace internal {
struct GlApi;
}

enum class GlBackend { kAuto, kOsMesa, kEgl };

std::string_view ToString(GlBackend backend);
// "auto" | "osmesa" | "egl"; throws hcpf::InputError naming the value otherwise.
GlBackend ParseGlBackend(std::string_view text);

// One EGL device as enumerated by eglQueryDevicesEXT: its index there and its
// device extension string (eglQueryDeviceStringEXT(EGL_EXTENSIONS)).
struct EglDeviceDescription {
  int index = 0;
  std::string extensions;
  bool software() const;
};

// One way of creating a context, tried in PlanGlAttempts' order.
struct GlAttempt {
  enum class Kind { kOsMesa, kEglDevice, kEglSurfaceless };
  Kind kind = Kind::kOsMesa;
  int device = -1;  // kEglDevice: the index in eglQueryDevicesEXT's list
  bool operator==(const GlAttempt&) const = default;
};

// The attempts for `backend` given the machine's EGL devices (see the order
// above; kOsMesa: OSMesa alone). Pure: the device selection logic, testable
// without the devices.
std::vector<GlAttempt> PlanGlAttempts(GlBackend backend,
                                      std::span<const EglDeviceDescription> devices);
// The machine's EGL devices (empty when EGL cannot enumerate them).
std::vector<EglDeviceDescription> QueryEglDevices();

struct GlInfo {
  std::string backend;  // "osmesa" | "egl"
  // How the context was made: "osmesa", "egl surfaceless", "egl device N
  // (hardware)" or "egl device N (software)".
  std::string platform;
  std::string vendor;    // GL_VENDOR
  std::string renderer;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version;   // GL_VERSION
  // GL_CONTEXT_PROFILE_MASK has the core bit. Mesa also says "Core Profile" in
  // GL_VERSION; NVIDIA's string ("4.5.0 NVIDIA 580.159.04") does not.
  bool core_profile = false;
  bool softpipe = false;
};

class GlContext {
 public:
  virtual ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Creates a context and makes it current on the calling thread. Throws
  // hcpf::InputError (CLI exit 2) when no requested backend works, with
  // each backend's failure in the message.
  static std::unique_ptr<GlContext> Create(GlBackend backend = GlBackend::kAuto);

  virtual void MakeCurrent() = 0;
  // Throws hcpf::RunError naming `where` if a GL error is pending (tests call
  // it after each case).
  void CheckNoError(const char* where) const;
  const GlInfo& info() const { return info_; }
  // The loaded GL entry points (private type; see src/gl_api.h).
  const internal::GlApi& api() const { return *api_; }

 protected:
  GlContext();
  // Loads the API through `loader`, fills info_ and logs it; throws on failure.
  // `platform` goes to GlInfo::platform.
  void Initialise(const std::string& backend, void* (*loader)(const char*),
                  const std::string& platform);

 private:
  GlInfo info_;
  std::unique_ptr<internal::GlApi> api_;
};

}  // namespace hcpf::renderer
