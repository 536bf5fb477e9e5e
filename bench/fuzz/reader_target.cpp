// libFuzzer target: the measurement reader (vehs/io/measurements.hpp) on the input as the bytes of
// a file named with the extension VEHS_FUZZ_EXTENSION (".csv": fuzz_csv_reader, ".npy":
// fuzz_npy_reader), read from memory through the stream entry point that read_measurements(path)
// uses for files: no file is written per execution. Twice: time column only, and with a drive
// column and dt given; the CSV target's second pass reads in chunks of 1-16 bytes, so that lines
// split across chunks (files over 4 MiB) are fuzzed too. Any vehs::Error is a correct answer; a
// crash, sanitizer report, hang or another exception is a finding.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "io/readers.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string name = std::string("fuzz") + VEHS_FUZZ_EXTENSION;
  for (const bool with_u : {false, true}) {
    try {
      vehs::ReadOptions o;
      o.read_u = with_u;
      o.dt = with_u ? 0.01 : 0.0;  // files without a time column too
      std::istringstream in(bytes);
      vehs::Dataset d;
      if (with_u && name.back() == 'v') {
        vehs::ReadSummary s;
        d = vehs::io_detail::read_csv(in, name, o, s, 1 + (size ? data[size - 1] % 16 : 0));
      } else {
        d = vehs::read_measurements(in, name, o);
      }
      (void)d.common_dt();
    } catch (const vehs::Error&) {
    }
  }
  return 0;
}
