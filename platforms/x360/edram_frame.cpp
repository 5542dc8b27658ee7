#include "platforms/x360/edram_frame.h"

#include <algorithm>
#include <stdexcept>

namespace parity::platforms::x360 {

void EdramFrame::declare(EdramSurface surface) {
  if (lookup(surface.name)) throw std::invalid_argument("EDRAM surface declared twice: " + surface.name);
  states_.push_back(State{std::move(surface), false});
}

EdramFrame::State& EdramFrame::find(std::string_view name) {
  for (State& s : states_)
    if (s.surface.name == name) return s;
  throw std::invalid_argument("unknown EDRAM surface: " + std::string(name));
}

const EdramFrame::State* EdramFrame::lookup(std::string_view name) const {
  for (const State& s : states_)
    if (s.surface.name == name) return &s;
  return nullptr;
}

bool EdramFrame::isLive(std::string_view name) const {
  const State* s = lookup(name);
  return s && s->live;
}

const EdramSurface& EdramFrame::surface(std::string_view name) const {
  const State* s = lookup(name);
  if (!s) throw std::invalid_argument("unknown EDRAM surface: " + std::string(name));
  return s->surface;
}

void EdramFrame::draw(std::string_view pass, const std::vector<std::string>& bound, DiagnosticList& out) {
  std::vector<EdramSurface> targets;
  for (const std::string& name : bound) targets.push_back(find(name).surface);
  checkBoundTargets(pass, targets, out);

  // Aliasing of contents that are still live (X1 overlap definition, X4 rules).
  for (const EdramSurface& writer : targets) {
    for (State& other : states_) {
      if (!other.live) continue;
      if (std::find(bound.begin(), bound.end(), other.surface.name) != bound.end()) continue;
      if (!tileRangesIntersect(tileRange(writer), tileRange(other.surface))) continue;
      const EdramSurface& t = other.surface;
      std::string_view code = "E_EDRAM_OVERLAP";
      std::string why = "its contents are still live (X1)";
      if (writer.role == SurfaceRole::GBuffer && t.role == SurfaceRole::GBuffer) {
        code = "E_GBUF_OVERLAP";
        why = "none of the G-buffers can overlap (X4)";
      } else if ((writer.role == SurfaceRole::LBuffer && t.isDepth) || (t.role == SurfaceRole::LBuffer && writer.isDepth)) {
        code = "E_LBUF_DEPTH_ALIAS";
        why = "the light pass still tests against the depth tiles (X4)";
      } else if (t.role == SurfaceRole::GBuffer && !t.isDepth) {
        code = "E_USE_BEFORE_RESOLVE";
        why = t.name + " has not been resolved yet (X4)";
      }
      out.report(code, {writer.name, t.name},
                 std::string(pass) + " writes " + writer.name + " " + formatTileRange(tileRange(writer)) +
                     " over " + t.name + " " + formatTileRange(tileRange(t)) + ": " + why);
      other.live = false;  // clobbered
    }
  }
  for (const std::string& name : bound) find(name).live = true;
}

void EdramFrame::resolve(std::string_view name, const ResolveRequest& request, std::string texture,
                         DiagnosticList& out) {
  State& s = find(name);
  checkResolveRequest(s.surface, request, out);
  // Colour contents are dead once resolved; depth stays live for later depth/stencil tests.
  if (!s.surface.isDepth) s.live = false;
  textures_.insert(std::move(texture));
}

void EdramFrame::sample(std::string_view pass, std::string_view name, DiagnosticList& out) {
  if (textures_.count(name)) return;
  if (const State* s = lookup(name)) {
    out.report("E_EDRAM_NOT_READABLE", {s->surface.name, std::string(pass)},
               std::string(pass) + " samples render target " + s->surface.name +
                   " directly; EDRAM is only reachable by the RB stage and resolves, resolve it to a texture (X1)");
  }
}

void EdramFrame::discard(std::string_view name) { find(name).live = false; }

}  // namespace parity::platforms::x360
