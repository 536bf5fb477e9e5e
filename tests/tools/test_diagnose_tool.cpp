// diagnose-vehs end to end through its main(): config → JSON per docs/outputs.md#diagnosis-file, a report that
// renders in headless Chromium with every figure, the model history across two model versions,
// and bad inputs rejected with exit status 1.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../diagnose/diagnose_fixtures.hpp"
#include "chromium.hpp"
#include "tool_runs.hpp"
#include "tools/diagnosis_file.hpp"
#include "tools/diagnosis_report.hpp"
#include "tools/history.hpp"
#include "tools/tools.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "tool_runs.hpp"

namespace fs = std::filesystem;
using namespace diag_test;

namespace {

int run(const std::vector<std::string>& args) {
  std::vector<std::string> a{"diagnose-vehs"};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  return vehs::tools::diagnose_main(static_cast<int>(argv.size()), argv.data());
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

}  // namespace

TEST_CASE("diagnose-vehs end to end: contract JSON, report in Chromium, history over two model versions",
          "[diagnose][app]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_diagnose_app";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // data with dry friction; version 1 misses it, version 2 has it
  DataSpec s;
  s.records = 32;
  s.samples = 6000;
  s.seed = 77;
  auto truth = bistable();
  truth.drift.push_back({vehs::Term::sign_y(), -0.1});
  vehs::canonicalize(truth.drift, "truth");
  const auto d = simulate(truth, s);
  vehs::write_measurements((dir / "data.npy").string(), d, {false, false, 17});
  vehs::write_json_atomically((dir / "v1.json").string(), vehs::model_to_json(fit(d, {"x", "x^3", "y"}, {"1", "x^2"})));
  vehs::write_json_atomically((dir / "v2.json").string(),
                              vehs::model_to_json(fit(d, {"x", "x^3", "y", "sign(y)"}, {"1", "x^2"})));
  const std::string cfg = (dir / "diagnose.json").string();
  write_text(cfg, R"({"model": ")" + (dir / "v1.json").string() + R"(", "data": [")" + (dir / "data.npy").string() +
                      R"("], "output": ")" + (dir / "out1.json").string() + R"(", "report": ")" +
                      (dir / "report").string() + R"(", "replicates": 2, "parameter_draws": 4, "fpk_cells": 60})");
  REQUIRE(run({cfg, "--quiet"}) == 0);
  // the next step of an inadequate model with a confirmed effect: a complete identify-vehs config
  // beside the report, shown as one command in the page's top card, that fits the effect
  const fs::path refit = dir / "report" / "refit.json";
  REQUIRE(fs::exists(refit));
  {
    const auto rc = read_json(refit.string());
    CHECK(rc["data"][0] == (dir / "data.npy").string());
    CHECK(rc["effects"].dump().find("coulomb_friction") != std::string::npos);
    CHECK(rc["output"] == (dir / "report" / "refit_model.json").string());
    const std::string page = chromium_dom((dir / "report" / "index.html").string());
    const auto card = page.find("<section id=\"top-card\"");
    REQUIRE(card != std::string::npos);
    const std::string top = page.substr(card, page.find("</section>", card) - card);
    CHECK(top.find("INADEQUATE") != std::string::npos);
    CHECK(top.find("<code>identify-vehs " + refit.string() + "</code>") != std::string::npos);
    CHECK(top.find("<th>standard error</th>") != std::string::npos);
    CHECK(page.find("Where the model fails") != std::string::npos);
    // identify-vehs --refit <diagnosis>: runs the config its refit_file names, no hand merge
    REQUIRE(vehs_tool_test::run_identify({"--refit", (dir / "out1.json").string(), "-q"}) == 0);
    const auto refitted = read_json((dir / "report" / "refit_model.json").string());
    CHECK(refitted["drift"].contains("sign(y)"));  // coulomb_friction, the recommended effect
  }
  // version 2 is the true model form: its "adequate" is a null check, at α = 5e-5 (false failure
  // per run if the p-values are valid; the calibration tests measure them at 1 %). Version 1's
  // "inadequate" and first suspect are power checks: over seed shifts of test_diagnose.cpp's
  // friction case (same μ, same size) every baseline was inadequate by orders of magnitude.
  REQUIRE(run({cfg, "--quiet", "--set", "model=\"" + (dir / "v2.json").string() + "\"", "--set",
               "output=\"" + (dir / "out2.json").string() + "\"", "--set", "label=\"with friction\"", "--set",
               "alpha=5e-5"}) == 0);

  const auto j1 = read_json((dir / "out1.json").string()), j2 = read_json((dir / "out2.json").string());
  for (const auto& j : {j1, j2}) {
    REQUIRE(j.contains("verdict"));
    CHECK((j["verdict"] == "adequate" || j["verdict"] == "inadequate"));
    CHECK(j["score"].is_number());
    for (const char* c : {"one_step", "pdf", "power", "acf"}) CHECK(j["components"].contains(c));
    REQUIRE(j["suspects"].is_array());
    for (const auto& sp : j["suspects"]) {
      CHECK(sp["effect"].is_string());
      CHECK(sp["evidence"].is_number());
      CHECK(sp["params"].is_object());
      CHECK(sp["add"]["effects"][0]["name"] == sp["effect"]);
    }
  }
  CHECK(j1["verdict"] == "inadequate");
  CHECK(j1["suspects"][0]["effect"] == "coulomb_friction");
  // confirmed before recommended (confirmation.hpp): the refit with the friction predicts the
  // held-out pieces better (power check, as above), and it is the recommendation
  INFO("conclusion: " << j1["conclusion"].dump() << "\nconfirmation: " << j1["confirmation"].dump());
  REQUIRE(j1["confirmation"]["ran"] == true);
  REQUIRE(j1["recommended"].is_array());
  REQUIRE(!j1["recommended"].empty());
  CHECK(j1["recommended"][0] == "coulomb_friction");
  CHECK(j1["conclusion"].get<std::string>().rfind("inadequate — add coulomb_friction", 0) == 0);
  CHECK(j1["outside_catalogue"] == false);
  // the next fit as a file beside the report, which identify-vehs runs as it is (no hand merge)
  REQUIRE(j1["refit_file"] == (dir / "report" / "refit.json").string());
  CHECK(j2["conclusion"] == "adequate");
  CHECK(j2["recommended"].empty());
  CHECK(j2["verdict"] == "adequate");
  CHECK(j2["refit_file"].is_null());  // nothing to refit: no file named
  CHECK(j2["score"].get<double>() < j1["score"].get<double>());
  // coulomb_friction is in version 2: not a suspect any more
  for (const auto& sp : j2["suspects"]) CHECK(sp["effect"] != "coulomb_friction");

  // history: two versions of the same data, plotted in the report
  const auto entries = vehs::tools::read_history((dir / "report" / "history.json").string());
  REQUIRE(entries.size() == 2);
  CHECK(entries[0]["version"] == 1);
  CHECK(entries[1]["version"] == 2);
  CHECK(entries[1]["label"] == "with friction");
  CHECK(entries[1]["score"].get<double>() < entries[0]["score"].get<double>());
  std::ifstream hcsv((dir / "report" / "history.csv").string());
  std::string line;
  int lines = 0;
  while (std::getline(hcsv, line)) ++lines;
  CHECK(lines == 3);

  // the page: every figure beside its CSV and script, all loaded by a real browser
  const std::string html = (dir / "report" / "index.html").string();
  REQUIRE(fs::exists(html));
  int figures = 0;
  for (const auto& e : fs::directory_iterator(dir / "report"))
    if (e.path().extension() == ".svg") {
      ++figures;
      CHECK(fs::exists(fs::path(e.path()).replace_extension(".gp")));
    }
  CHECK(figures >= 12);
  CHECK(fs::exists(dir / "report" / "summary.json"));
  CHECK(chromium_figure_status(html) == "figures-loaded: " + std::to_string(figures) + "/" + std::to_string(figures));

  // what a person sees on the page (the DOM after Chromium loaded it): the verdict and the next
  // step before the first figure, links to both versions' reports (each kept), no debug lines
  const std::string dom = chromium_dom(html);
  REQUIRE(!dom.empty());
  std::string shown = dom.substr(dom.find("<body"));  // the body without its scripts
  for (auto a = shown.find("<script"); a != std::string::npos; a = shown.find("<script"))
    shown.erase(a, shown.find("</script>", a) + 9 - a);
  CHECK(shown.find("figures-loaded") == std::string::npos);
  const auto step = dom.find("Next step:");
  REQUIRE(step != std::string::npos);
  CHECK(step < dom.find("<figure"));
  CHECK(dom.find("ADEQUATE") < dom.find("<figure"));
  // version 2 is adequate: no failure section, no stale refit config beside the report
  CHECK(dom.find("Where the model fails") == std::string::npos);
  CHECK_FALSE(fs::exists(refit));
  for (const char* v : {"versions/v1.html", "versions/v2.html"}) {
    CHECK(dom.find(v) != std::string::npos);
    CHECK(fs::exists(dir / "report" / v));
  }
  const std::string v1 = [&] {
    std::ifstream in(dir / "report" / "versions" / "v1.html");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  CHECK(v1.find("INADEQUATE") != std::string::npos);  // version 1's page, not overwritten
  CHECK(v1.find("Next step: add coulomb_friction") != std::string::npos);
  // labels rendered literally (no enhanced-text subscripts: "one_step" stays one word), units
  // named on the axes, and the history's reference line for an adequate model
  auto svg = [&](const char* name) {
    std::ifstream in(dir / "report" / name);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  CHECK(svg("components.svg").find(">one_step<") != std::string::npos);
  CHECK(svg("x_psd.svg").find("frequency [1/time]") != std::string::npos);
  CHECK(svg("history.svg").find("adequate (about") != std::string::npos);

  // --fail-on-inadequate: exit status 3 for version 1's verdict
  CHECK(run({cfg, "--quiet", "--fail-on-inadequate", "--set", "output=\"" + (dir / "out3.json").string() + "\"",
             "--set", "history=\"" + (dir / "history3.json").string() + "\""}) == 3);
}

TEST_CASE("diagnose-vehs rejects bad inputs with exit status 1 and writes nothing", "[diagnose][app][errors]") {
  const fs::path dir = fs::temp_directory_path() / "vehs_diagnose_app_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  DataSpec s;
  s.records = 2;
  s.samples = 3000;
  const auto d = simulate(bistable(), s);
  vehs::write_measurements((dir / "data.csv").string(), d, {false, false, 17});
  vehs::write_json_atomically((dir / "model.json").string(), vehs::model_to_json(bistable()));
  const std::string base = R"("data": [")" + (dir / "data.csv").string() + R"("], "output": ")" +
                           (dir / "out.json").string() + R"(", "report": ")" + (dir / "report").string() + "\"";
  auto cfg = [&](const std::string& name, const std::string& body) {
    const std::string p = (dir / name).string();
    write_text(p, "{" + body + "}");
    return p;
  };
  // missing model file, unknown key, wrong dt, model identified at another dt, bad history file
  CHECK(run({cfg("a.json", R"("model": ")" + (dir / "nope.json").string() + "\", " + base), "--quiet"}) == 1);
  CHECK(run({cfg("b.json", R"("model": ")" + (dir / "model.json").string() + "\", \"bogus\": 1, " + base), "--quiet"}) == 1);
  CHECK(run({cfg("c.json", R"("model": ")" + (dir / "model.json").string() + "\", \"dt\": 0.001, " + base), "--quiet"}) == 1);
  auto stated = vehs::model_to_json(bistable());
  stated["sampling"] = {{"dt", 0.05}};
  vehs::write_json_atomically((dir / "stated.json").string(), stated);
  CHECK(run({cfg("d.json", R"("model": ")" + (dir / "stated.json").string() + "\", " + base), "--quiet"}) == 1);
  fs::create_directories(dir / "report");
  write_text((dir / "report" / "history.json").string(), "not json");
  CHECK(run({cfg("e.json", R"("model": ")" + (dir / "model.json").string() + "\", \"suspects\": false, " + base), "--quiet"}) == 1);
  // a user effect that is not one, or listed twice
  fs::remove_all(dir / "report");
  for (const std::string& users : {std::string(R"([{"name": "f"}])"), std::string(R"([{"name": "f", "drift": {"a": "x^^2"}}])"),
                                   std::string(R"([{"name": "f", "drift": {"a": "x^2"}}, {"name": "f", "drift": {"b": "x^4"}}])")})
    CHECK(run({cfg("f.json", R"("model": ")" + (dir / "model.json").string() + "\", \"user_effects\": " + users + ", " + base),
               "--quiet"}) == 1);
  CHECK_FALSE(fs::exists(dir / "out.json"));
}

TEST_CASE("diagnose-vehs's refit config and suspects' fragments hold a user effect's definition", "[diagnose][app][user]") {
  vehs::diagnose::Result r;
  r.verdict = vehs::diagnose::Verdict::Inadequate;
  r.confirmation.ran = true;
  r.recommended = {"directional_friction"};
  vehs::UserEffect u;
  u.name = "directional_friction";
  u.params = {{"Fp", vehs::Term::parse("-(y>0)"), false}, {"Fm", vehs::Term::parse("(y<0)"), false}};
  r.user_effects = {u};
  const nlohmann::ordered_json definition = {{"name", "directional_friction"}, {"drift", {{"Fm", "(y<0)"}, {"Fp", "-(y>0)"}}}};
  const auto cfg = vehs::tools::refit_config(r, bistable());
  INFO(cfg.dump());
  REQUIRE(cfg["effects"].size() == 1);
  auto same = [&](const nlohmann::ordered_json& j) {  // (the order of the parameters aside)
    return nlohmann::json::parse(j.dump()) == nlohmann::json::parse(definition.dump());
  };
  CHECK(same(cfg["effects"][0]));
  vehs::diagnose::Suspect sp;
  sp.effect = "directional_friction";
  CHECK(same(vehs::tools::suspect_add_fragment(sp, r.user_effects)["effects"][0]));
  sp.effect = "coulomb_friction";
  CHECK(vehs::tools::suspect_add_fragment(sp, r.user_effects)["effects"][0]["name"] == "coulomb_friction");
  // the definition read back is the effect
  const vehs::UserEffect back = vehs::user_effect_from_json(nlohmann::json::parse(cfg["effects"][0].dump()), "refit");
  CHECK(back.name == u.name);
  REQUIRE(back.params.size() == 2);
  const std::vector<vehs::UserEffect> read{back};
  CHECK(vehs::find_user_effect(read, "directional_friction") == &read[0]);
}

TEST_CASE("diagnose-vehs's next step lists every recommended effect in its identify fragment", "[diagnose][app]") {
  // an outside tester: "add impact_stop, colored_noise" beside "effects": ["impact_stop"]
  vehs::diagnose::Result r;
  r.verdict = vehs::diagnose::Verdict::Inadequate;
  r.confirmation.ran = true;
  r.recommended = {"coulomb_friction", "harmonic_forcing"};
  vehs::diagnose::Confirmation c;
  c.effect = "harmonic_forcing";
  c.confirmed = true;
  c.per_record_phase = true;
  r.confirmation.effects.push_back(c);
  const std::string s = vehs::tools::next_step(r);
  INFO(s);
  CHECK(s.find("\"effects\": [\"coulomb_friction\", \"harmonic_forcing\"], \"likelihood\": {\"per_record_phase\": true}") !=
        std::string::npos);
  // with the model: every key of the confirming refit (an outside tester: "no re-selection" named no key)
  vehs::Model m = bistable();
  m.effects.push_back(vehs::Effect{vehs::EffectId::ColoredNoise, {}, {}});
  r.confirmation.by_likelihood = true;
  const std::string full = vehs::tools::next_step(r, &m);
  INFO(full);
  const auto cfg = vehs::tools::refit_config(r, m);
  CHECK(full.find(cfg.dump()) != std::string::npos);
  CHECK(cfg["drift_library"].size() == m.drift.size());
  CHECK(cfg["diffusion_library"].size() == m.diffusion.size());
  CHECK(cfg["effects"] == nlohmann::ordered_json({"colored_noise", "coulomb_friction", "harmonic_forcing"}));
  CHECK(cfg["sparsity"] == "none");
  CHECK(cfg["likelihood"]["select"] == false);
  CHECK(cfg["likelihood"]["use"] == "always");  // a moment-fitted model: the refit was by the likelihood
  CHECK(cfg["likelihood"]["per_record_phase"] == true);
  r.recommended.clear();
  CHECK(vehs::tools::refit_config(r, m).is_null());
}
