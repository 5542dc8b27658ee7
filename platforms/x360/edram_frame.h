// A frame on the Xbox 360 as a sequence of draws, resolves and texture reads, checked against
// the EDRAM rules in order (X1, X3, X4).
//
// A surface's contents are live from the draw that writes them until they are resolved (colour)
// or discarded; depth stays live after a resolve because later passes test against it. A draw
// whose targets alias the tiles of another live surface clobbers it, and is reported with the
// most specific code: E_GBUF_OVERLAP, E_LBUF_DEPTH_ALIAS, E_USE_BEFORE_RESOLVE (a G-buffer colour
// target not yet resolved), else E_EDRAM_OVERLAP. Sampling a surface instead of a resolved
// texture is E_EDRAM_NOT_READABLE.
#pragma once

#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "platforms/common/diagnostics.h"
#include "platforms/common/platform_params.h"
#include "platforms/x360/edram.h"
#include "platforms/x360/resolve.h"

namespace parity::platforms::x360 {

class EdramFrame {
 public:
  explicit EdramFrame(PlatformParams params = {}) : params_(params) {}

  // Declares a surface (name, base, pitch, MSAA, format, role). Names are unique.
  void declare(EdramSurface surface);
  // A draw pass writing `bound` (surface names): X1 pass rules, then aliasing of live contents.
  void draw(std::string_view pass, const std::vector<std::string>& bound, DiagnosticList& out);
  // Resolves `surface` into the texture `texture` (X3 request checks).
  void resolve(std::string_view surface, const ResolveRequest& request, std::string texture, DiagnosticList& out);
  // A shader in `pass` samples `name`: a resolved texture is fine, a surface is not.
  void sample(std::string_view pass, std::string_view name, DiagnosticList& out);
  // The surface's contents are no longer needed.
  void discard(std::string_view surface);

  bool isLive(std::string_view surface) const;
  const EdramSurface& surface(std::string_view name) const;

 private:
  struct State {
    EdramSurface surface;
    bool live = false;
  };
  State& find(std::string_view name);
  const State* lookup(std::string_view name) const;

  PlatformParams params_;
  std::vector<State> states_;
  std::set<std::string, std::less<>> textures_;
};

}  // namespace parity::platforms::x360
