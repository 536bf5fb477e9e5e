// Does a model reproduce measured records? Reads a model file (docs/model-file.md) and a CSV of
// records (docs/measurements.md), runs vehs::diagnose::diagnose and prints the verdict, the score,
// the failing components and the ranked suspects (effects of the catalogue the data ask for).
//   diagnose_csv MODEL.json RECORDS.csv
// (the paper_pipeline example writes such a pair). Exit status 0 whatever the verdict,
// 1 on an error (a one-line message naming the file, record or field).
#include <cstdio>

#include <vehs/diagnose/diagnose.hpp>
#include <vehs/io/measurements.hpp>
#include <vehs/io/model_file.hpp>

int main(int argc, char** argv) try {
  if (argc != 3) {
    std::fprintf(stderr, "usage: diagnose_csv MODEL.json RECORDS.csv\n");
    return 2;
  }
  const vehs::Model model = vehs::load_model_file(argv[1]);
  const vehs::Dataset data = vehs::read_measurements(argv[2]);  // columns t, x [, traj, u]

  vehs::diagnose::Options options;  // the lens of the model's fit, alpha = 0.01
  const vehs::diagnose::Result r = vehs::diagnose::diagnose(model, data, options);

  std::printf("%zu records, %zu samples: %s, score %.3g (about %.2g expected of an adequate model)\n",
              r.records, r.samples, vehs::enum_to_string(vehs::diagnose::kVerdictNames, r.verdict).c_str(),
              r.score, r.score_expected_adequate);
  for (const vehs::diagnose::Component& c : r.components)
    if (c.test.available)
      std::printf("  %-22s p = %-10.3g %s%s\n", c.name.c_str(), c.test.p_value, c.what.c_str(),
                  c.test.p_value < r.threshold ? "  <- fails" : "");
  std::printf("suspects (held-out log-likelihood gain, nats):\n");
  for (const vehs::diagnose::Suspect& s : r.suspects.ranked)
    std::printf("  %-28s %9.2f  z = %5.2f%s\n", s.effect.c_str(), s.evidence, s.z,
                s.significant ? "  significant" : "");
  return 0;
} catch (const vehs::Error& e) {
  std::fprintf(stderr, "diagnose_csv: %s\n", e.what());
  return 1;
}
