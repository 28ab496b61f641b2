#pragma once
// Internal (for the .cpp files that call OpenMesh): OpenMesh reports to its global streams, and
// the library must not print, so they are muted for the lifetime of this guard and restored
// to their previous state afterwards.
#include <OpenMesh/Core/System/omstream.hh>

namespace cw4d::detail {

class MuteOpenMesh {
 public:
  MuteOpenMesh() : err_(::omerr().is_enabled()), log_(::omlog().is_enabled()) {
    ::omerr().disable();
    ::omlog().disable();
  }
  ~MuteOpenMesh() {
    if (err_) ::omerr().enable();
    if (log_) ::omlog().enable();
  }
  MuteOpenMesh(const MuteOpenMesh&) = delete;
  MuteOpenMesh& operator=(const MuteOpenMesh&) = delete;

 private:
  bool err_, log_;
};

}  // namespace cw4d::detail
