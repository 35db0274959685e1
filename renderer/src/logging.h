#pragma once
// Private: the renderer's named spdlog logger ("renderer").

#include <spdlog/spdlog.h>

#include <memory>

namespace hcpf::renderer {

inline std::shared_ptr<spdlog::logger> Logger() {
  static std::shared_ptr<spdlog::logger> logger = [] {
    auto existing = spdlog::get("renderer");
    if (existing) return existing;
    // Share the default logger's sinks (the CLI sends them to stderr).
    auto l = std::make_shared<spdlog::logger>("renderer", spdlog::default_logger()->sinks().begin(),
                                              spdlog::default_logger()->sinks().end());
    l->set_level(spdlog::default_logger()->level());
    spdlog::register_logger(l);
    return l;
  }();
  return logger;
}

}  // namespace hcpf::renderer
