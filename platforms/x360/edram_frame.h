// A frame on the Xbox 360 as a sequence of passes, resolves and texture reads, checked against
// the EDRAM rules in order (X1, X3, X4). The x360 rules (x360_rules.cpp) keep one per plan (the
// surfaces placed together) and feed it the technique's real passes and resolves.
//
// A surface's contents are live from the pass that writes them until they are resolved (colour)
// or replaced; depth stays live after a resolve because later passes test against it. A pass
// whose written surfaces alias the tiles of another surface's live contents clobbers them:
//  * at once when those contents still await the resolve a later pass reads them through (a
//    colour target that is resolved later), and
//  * when the clobbered contents are used afterwards: a pass that loads them (LoadOp::Load, the
//    depth a light pass tests against) or a resolve of them.
// The code is the most specific one: E_GBUF_OVERLAP (G-buffer over G-buffer), E_LBUF_DEPTH_ALIAS
// (the L-buffer and depth), E_USE_BEFORE_RESOLVE (a G-buffer colour target not yet resolved),
// else E_EDRAM_OVERLAP. Surfaces bound together get the X1 rules of a pass (checkBoundTargets).
// Sampling a surface instead of a resolved texture is E_EDRAM_NOT_READABLE.
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
  // `resolvedLater`: a later pass reads its contents through a resolve (colour by default).
  void declare(EdramSurface surface);
  void declare(EdramSurface surface, bool resolvedLater);

  struct Binding {
    std::string surface;
    bool loads = false;   // keeps its contents (LoadOp::Load): a use of them
    bool writes = true;   // cleared or drawn into by the pass
  };
  // A pass binding `bound`: the X1 rules of the bound set, the use of clobbered contents by the
  // surfaces it loads, then the clobbering of other surfaces' live contents by what it writes.
  void pass(std::string_view pass, const std::vector<Binding>& bound, DiagnosticList& out);
  // The same with every bound surface written and none loaded.
  void draw(std::string_view pass, const std::vector<std::string>& bound, DiagnosticList& out);
  // A draw of `pass` writes `surface`, which the pass bound without writing it so far (a depth it
  // loaded and now writes).
  void write(std::string_view pass, std::string_view surface, DiagnosticList& out);
  // Resolves `surface` into the texture `texture` (X3 request checks, clobbered contents).
  void resolve(std::string_view surface, const ResolveRequest& request, std::string texture, DiagnosticList& out);
  // A shader in `pass` samples `name`: a resolved texture is fine, a surface is not.
  void sample(std::string_view pass, std::string_view name, DiagnosticList& out);
  // The surface's contents are no longer needed.
  void discard(std::string_view surface);

  bool isLive(std::string_view surface) const;
  bool has(std::string_view surface) const { return lookup(surface) != nullptr; }
  const EdramSurface& surface(std::string_view name) const;

 private:
  struct State {
    EdramSurface surface;
    bool resolvedLater = false;
    bool live = false;
    // Set when another surface's write clobbered the live contents: the code and what to say
    // when they are used.
    std::string clobberCode, clobberMessage;
    std::vector<std::string> clobberTargets;
  };
  State& find(std::string_view name);
  const State* lookup(std::string_view name) const;
  // `writer`'s tiles written in `pass` over the live contents of the surfaces not bound with it.
  void clobber(std::string_view pass, const State& writer, const std::vector<std::string>& bound, DiagnosticList& out);
  void use(std::string_view how, State& s, DiagnosticList& out);

  PlatformParams params_;
  std::vector<State> states_;
  std::set<std::string, std::less<>> textures_;
  std::vector<std::string> bound_;  // the surfaces of the last pass
};

}  // namespace parity::platforms::x360
