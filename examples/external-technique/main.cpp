// The parity command with one more technique. Registration comes first: the children of
// `run` and `test` are forked from the state startForkServer sees.
#include "harness/cli/cli.h"
#include "harness/run/process.h"
#include "techniques/technique.h"
#include "unlit_albedo.h"

int main(int argc, char** argv) {
  parity::techniques::registerTechnique(
      {"unlit-albedo", "unlit albedo (an example technique built outside parity): diffuse colour, no light",
       [] { return std::make_unique<albedo::UnlitAlbedo>(); }});
  parity::harness::startForkServer(&parity::harness::runCli);
  return parity::harness::runCli(argc, argv);
}
