// libFuzzer target: the measurement reader (vehs/io/measurements.hpp) on a file holding the input,
// named with the extension VEHS_FUZZ_EXTENSION (".csv": fuzz_csv_reader, ".npy": fuzz_npy_reader;
// the readers take paths: the input is written to a file in /dev/shm, or $TMPDIR, once per
// execution). Any vehs::Error is a correct answer; a crash, sanitizer report, hang or another
// exception is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

namespace {

std::string scratch_path() {
  const char* dir = ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : (std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
  return std::string(dir) + "/vehs_fuzz_" + std::to_string(::getpid()) + VEHS_FUZZ_EXTENSION;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = scratch_path();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  for (const bool with_u : {false, true}) {
    try {
      vehs::ReadOptions o;
      o.read_u = with_u;
      o.dt = with_u ? 0.01 : 0.0;  // files without a time column too
      const vehs::Dataset d = vehs::read_measurements(path, o);
      (void)d.common_dt();
    } catch (const vehs::Error&) {
    }
  }
  return 0;
}
