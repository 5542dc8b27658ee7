// `parity list` (backends with their renderer, techniques, scenes) and the hidden `probe` that
// list runs in a child process per backend.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <map>

#include "harness/cli/commands.h"
#include "harness/run/devices.h"
#include "harness/run/process.h"
#include "rhi/rhi.h"
#include "scene/scene.h"
#include "techniques/technique.h"

namespace parity::harness {

namespace {

struct BackendStatus {
  std::string name;
  bool available = false;
  std::string reason;  // when unavailable
  rhi::DeviceInfo info;
};

// Probes one backend (one of its adapters, when given) in this process and prints its status as
// JSON (hidden `probe` command); with `adapters`, the names of the backend's adapters instead.
int probeBackend(const std::string& backend, const std::string& glProvider, const std::string& adapter, bool adapters) {
  if (adapters) {
    std::cout << nlohmann::json{{"adapters", rhi::adapterNames(backend)}}.dump() << std::endl;
    return 0;
  }
  rhi::DeviceDesc desc;
  desc.backend = backend;
  desc.glContextProvider = glProvider;
  desc.adapter = adapter;
  std::string why;
  auto device = rhi::createDevice(desc, &why);
  nlohmann::json j;
  j["name"] = backend;
  j["available"] = device != nullptr;
  if (device) {
    const rhi::DeviceInfo& i = device->info();
    j["api"] = i.api;
    j["renderer"] = i.renderer;
    j["driver"] = i.driver;
    j["context_provider"] = i.contextProvider;
  } else {
    j["reason"] = why;
  }
  std::cout << j.dump() << std::endl;
  return 0;
}

// Each backend is probed in a child process: GL and Vulkan never share a process, and a driver
// that crashes while loading makes its backend unavailable instead of ending the command.
BackendStatus queryBackend(const std::string& backend, const std::string& glProvider, const std::string& adapter = "") {
  BackendStatus s;
  s.name = backend;
  std::vector<std::string> args = {selfExecutable(), "probe", "--backend", backend, "--gl-provider", glProvider};
  if (!adapter.empty()) args.insert(args.end(), {"--adapter", adapter});
  ProcessResult p = runProcess(args, 60);
  if (!p.startError.empty() || p.timedOut || p.crashed || p.exitCode != 0) {
    s.reason = p.timedOut ? "probe timed out"
               : p.crashed ? "probe crashed (signal " + std::to_string(p.signal) + ")"
                           : "probe failed: " + p.startError + p.err;
    return s;
  }
  try {
    nlohmann::json j = nlohmann::json::parse(p.out);
    s.available = j.at("available").get<bool>();
    if (s.available) {
      s.info.backend = backend;
      s.info.api = j.value("api", "");
      s.info.renderer = j.value("renderer", "");
      s.info.driver = j.value("driver", "");
      s.info.contextProvider = j.value("context_provider", "");
    } else {
      s.reason = j.value("reason", "unknown reason");
    }
  } catch (const std::exception& e) {
    s.reason = std::string("probe printed no status: ") + e.what();
  }
  return s;
}

// A device: a backend with one of its drivers, named stably from the driver ("gl-llvmpipe",
// "gl-zink", "vk-lavapipe"; a vendor's: the first word of its renderer, "gl-nvidia").
struct DeviceStatus {
  std::string name, adapter;
  BackendStatus status;
};

// Every device here: each backend's adapters (rhi::adapterNames), probed one child each, and the
// backend's default device where it is none of them (a vendor's GL driver).
std::vector<DeviceStatus> queryDevices(const std::vector<BackendStatus>& defaults, const std::string& glProvider) {
  std::vector<DeviceStatus> out;
  for (const BackendStatus& d : defaults) {
    std::vector<std::string> adapters;
    ProcessResult p = runProcess({selfExecutable(), "probe", "--backend", d.name, "--adapters"}, 60);
    nlohmann::json j = nlohmann::json::parse(p.out, nullptr, false);
    if (!p.died() && p.exitCode == 0 && j.is_object()) adapters = j.value("adapters", std::vector<std::string>{});
    bool defaultSeen = !d.available;
    for (const std::string& a : adapters) {
      DeviceStatus s{"", a, queryBackend(d.name, glProvider, a)};
      s.name = deviceName(d.name, a, s.status.info);
      defaultSeen |= s.status.available && s.status.info.renderer == d.info.renderer;
      out.push_back(s);
    }
    if (!defaultSeen) out.push_back({deviceName(d.name, "", d.info), "", d});
  }
  // Two physical devices of one kind: numbered in the order the backend lists them.
  std::map<std::string, int> seen;
  for (DeviceStatus& s : out)
    if (int n = ++seen[s.name]; n > 1) s.name += "-" + std::to_string(n);
  return out;
}

int cmdList(bool json, const std::string& glProvider) {
  std::vector<BackendStatus> backends;
  for (const std::string& b : rhi::compiledBackends()) backends.push_back(queryBackend(b, glProvider));
  const std::vector<DeviceStatus> devices = queryDevices(backends, glProvider);
  if (json) {
    nlohmann::json j;
    for (const BackendStatus& b : backends) {
      nlohmann::json e{{"name", b.name}, {"available", b.available}};
      if (b.available) {
        e["api"] = b.info.api;
        e["renderer"] = b.info.renderer;
        e["driver"] = b.info.driver;
        if (!b.info.contextProvider.empty()) e["context_provider"] = b.info.contextProvider;
      } else {
        e["reason"] = b.reason;
      }
      j["backends"].push_back(e);
    }
    j["devices"] = nlohmann::json::array();
    for (const DeviceStatus& d : devices) {
      nlohmann::json e{{"name", d.name}, {"backend", d.status.name}, {"adapter", d.adapter}, {"available", d.status.available}};
      if (d.status.available) e.update({{"renderer", d.status.info.renderer}, {"driver", d.status.info.driver}, {"api", d.status.info.api}});
      else e["reason"] = d.status.reason;
      j["devices"].push_back(e);
    }
    for (const auto& t : techniques::techniqueRegistry())
      j["techniques"].push_back({{"name", t.name}, {"description", t.description}});
    for (const std::string& s : scene::sceneNames()) j["scenes"].push_back({{"name", s}, {"cameras", scene::cameraNames(s)}});
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::printf("backends:\n");
  for (const BackendStatus& b : backends) {
    if (b.available)
      std::printf("  %-4s available    %s | %s | %s%s\n", b.name.c_str(), b.info.renderer.c_str(), b.info.api.c_str(),
                  b.info.driver.c_str(), b.info.contextProvider.empty() ? "" : (" | " + b.info.contextProvider).c_str());
    else
      std::printf("  %-4s unavailable  %s\n", b.name.c_str(), b.reason.c_str());
  }
  std::printf("devices:\n");
  for (const DeviceStatus& d : devices) {
    if (d.status.available)
      std::printf("  %-12s available    %s | %s\n", d.name.c_str(), d.status.info.renderer.c_str(), d.status.info.driver.c_str());
    else
      std::printf("  %-12s unavailable  %s\n", d.name.c_str(), d.status.reason.c_str());
  }
  std::printf("techniques:\n");
  for (const auto& t : techniques::techniqueRegistry()) std::printf("  %-10s %s\n", t.name.c_str(), t.description.c_str());
  std::printf("scenes:\n");
  for (const std::string& s : scene::sceneNames()) {
    std::string cams;
    for (const std::string& c : scene::cameraNames(s)) cams += (cams.empty() ? "" : ", ") + c;
    std::printf("  %-10s cameras: %s\n", s.c_str(), cams.c_str());
  }
  return 0;
}

}  // namespace

void registerListCommands(CLI::App& app, CommandSet& commands) {
  struct ListState {
    bool json = false;
    std::string provider = "egl";
  };
  auto listState = std::make_shared<ListState>();
  CLI::App* list = app.add_subcommand("list", "backends and devices with availability and renderer, techniques, scenes");
  list->add_flag("--json", listState->json, "machine-readable output");
  list->add_option("--gl-provider", listState->provider, "GL context provider to probe")
      ->check(CLI::IsMember({"egl", "osmesa"}));
  commands.add(list, [listState] { return cmdList(listState->json, listState->provider); });


  struct ProbeState {
    std::string backend, provider = "egl", adapter;
    bool adapters = false;
  };
  auto probeState = std::make_shared<ProbeState>();
  CLI::App* probe = app.add_subcommand("probe", "");  // hidden: used by list in child processes
  probe->group("");
  probe->add_option("--backend", probeState->backend)->required();
  probe->add_option("--gl-provider", probeState->provider);
  probe->add_option("--adapter", probeState->adapter);
  probe->add_flag("--adapters", probeState->adapters);
  commands.add(probe, [probeState] {
    return probeBackend(probeState->backend, probeState->provider, probeState->adapter, probeState->adapters);
  });
}

}  // namespace parity::harness
