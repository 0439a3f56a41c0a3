// One libFuzzer executable per target (clang, -DBARYLAB_FUZZ=ON): barylab_libfuzz_<target>,
// the target chosen at compile time (BARYLAB_FUZZ_TARGET). tools/fuzz.sh runs them from the
// seed corpus that `barylab_fuzz seeds DIR` writes.
#include "barylab_fuzz_targets.h"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>


namespace
{
const barylab::fuzz::Target* target = nullptr;
std::string scratch;
}

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  namespace fuzz = barylab::fuzz;
#ifdef BARYLAB_FUZZ_CLI
  fuzz::RegisterCliTarget();
#endif
  fuzz::Quiet();
  target = fuzz::FindTarget(BARYLAB_FUZZ_TARGET);
  if (!target)
  {
    std::fprintf(stderr, "no fuzz target '%s' in this build\n", BARYLAB_FUZZ_TARGET);
    std::abort();
  }
  char dir[] = "/tmp/barylab-libfuzz-XXXXXX";
  if (!mkdtemp(dir))
    std::abort();
  scratch = dir;
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  barylab::fuzz::RunOne(*target, scratch, data, size);
  return 0;
}
