// targets[i].model_digest and a mesh occluder's: the resolved YAML names a
// model by its content as well as its path, so a run's key (its resolved
// scenario's hash) moves when a model is edited in place, and a resolved
// scenario whose model changed since is refused.

#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/scenario.h"
#include "support/process.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;
using testing::kMinimal;

// A quad of 4 x 2 m, 1 m high at one corner, coloured by `mtl` (its material
// library, named with a space as an .obj may).
constexpr const char* kObj =
    "mtllib box paint.mtl\n"
    "usemtl red\n"
    "v 0 0 0\nv 4 0 0\nv 4 2 0\nv 0 2 1\n"
    "f 1 2 3\nf 1 3 4\n";

// The message of the InputError loading throws ("" when it loads).
std::string ModelLoadError(const std::string& text, const std::vector<Override>& overrides) {
  try {
    LoadScenarioText(text, "s.yaml", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// XXH3-128 of the length-prefixed parts, written out here as docs/scenario.md
// states the digest, not by the code under test.
std::string Xxh128Of(const std::vector<std::string>& parts) {
  std::string all;
  for (const std::string& p : parts) {
    const uint64_t size = p.size();
    all.append(reinterpret_cast<const char*>(&size), sizeof(size));
    all += p;
  }
  const XXH128_hash_t h = XXH3_128bits(all.data(), all.size());
  char hex[33];
  std::snprintf(hex, sizeof(hex), "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return hex;
}

TEST(ModelDigest, PinsTheModelAndItsMaterialsInTheResolvedYaml) {
  const fs::path dir = hcpf::testing::FreshDir("model-digest");
  const std::string mtl = "newmtl red\nKd 1 0 0\n";
  WriteTextFile((dir / "box.obj").string(), kObj);
  WriteTextFile((dir / "box paint.mtl").string(), mtl);
  const std::vector<Override> model = {{"targets.0.model", (dir / "box.obj").string()}};
  const Scenario s = LoadScenarioText(kMinimal, "s.yaml", model);
  EXPECT_EQ(s.world.targets[0].model_digest, Xxh128Of({kObj, "box paint.mtl", mtl}));
  EXPECT_EQ(s.world.targets[1].model_digest, "");  // a box: no file

  // Written beside the model, and only there; read back to the same scenario.
  const std::string resolved = ToResolvedYaml(s);
  EXPECT_NE(resolved.find("    model_digest: \"" + s.world.targets[0].model_digest + "\"\n"),
            std::string::npos)
      << resolved;
  EXPECT_EQ(resolved.find("model_digest"), resolved.rfind("model_digest")) << resolved;
  EXPECT_EQ(ToResolvedYaml(LoadScenarioText(resolved, "scenario.resolved.yaml")), resolved);

  // The same files elsewhere: the same digest (content, not place).
  const fs::path copy = hcpf::testing::FreshDir("model-digest-copy");
  fs::copy(dir, copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  EXPECT_EQ(LoadScenarioText(kMinimal, "s.yaml", {{"targets.0.model", (copy / "box.obj").string()}})
                .world.targets[0]
                .model_digest,
            s.world.targets[0].model_digest);

  // The material edited in place: another run (config hash), and the resolved
  // YAML of before refused where its digest is, with the digest now.
  WriteTextFile((dir / "box paint.mtl").string(), "newmtl red\nKd 0 1 0\n");
  const Scenario edited = LoadScenarioText(kMinimal, "s.yaml", model);
  EXPECT_NE(edited.world.targets[0].model_digest, s.world.targets[0].model_digest);
  EXPECT_NE(ConfigHash(edited), ConfigHash(s));
  std::string error;
  try {
    LoadScenarioText(resolved, "scenario.resolved.yaml");
  } catch (const InputError& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("scenario.resolved.yaml:"), std::string::npos) << error;
  EXPECT_NE(error.find("targets[0].model_digest: expected " + edited.world.targets[0].model_digest),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("found \"" + s.world.targets[0].model_digest + "\""), std::string::npos)
      << error;

  // A material library gone: refused at the model, naming the file.
  fs::remove(dir / "box paint.mtl");
  error = ModelLoadError(kMinimal, model);
  EXPECT_NE(error.find("targets[0].model"), std::string::npos) << error;
  EXPECT_NE(error.find("box paint.mtl"), std::string::npos) << error;
}

TEST(ModelDigest, AMeshOccludersModelIsPinnedToo) {
  const fs::path dir = hcpf::testing::FreshDir("model-digest-occluder");
  WriteTextFile((dir / "box.obj").string(), kObj);
  WriteTextFile((dir / "box paint.mtl").string(), "newmtl red\nKd 1 0 0\n");
  const std::string text = std::string(kMinimal) + "world: {occluders: [{kind: mesh, model: \"" +
                           (dir / "box.obj").string() + "\", at: [30, 30]}]}\n";
  const Scenario s = LoadScenarioText(text, "s.yaml");
  const std::string digest = s.world.occluders.at(0).model_digest;
  EXPECT_EQ(digest.size(), 32u);
  const std::string resolved = ToResolvedYaml(s);
  EXPECT_NE(resolved.find("model_digest: \"" + digest + "\""), std::string::npos) << resolved;
  WriteTextFile((dir / "box.obj").string(), std::string(kObj) + "v 9 9 9\n");
  const std::string error = ModelLoadError(resolved, {});
  EXPECT_NE(error.find("world.occluders[0].model_digest: expected "), std::string::npos) << error;
}

TEST(ModelDigest, ADigestIsCheckedAndGoesWithTheModelAnOverrideReplaces) {
  const fs::path dir = hcpf::testing::FreshDir("model-digest-override");
  WriteTextFile((dir / "box.obj").string(), kObj);
  WriteTextFile((dir / "box paint.mtl").string(), "newmtl red\nKd 1 0 0\n");
  WriteTextFile((dir / "other.obj").string(), "v 0 0 0\nv 3 0 0\nv 3 1 1\nf 1 2 3\n");
  const std::string box = (dir / "box.obj").string();
  const std::string other = (dir / "other.obj").string();
  const std::string resolved =
      ToResolvedYaml(LoadScenarioText(kMinimal, "s.yaml", {{"targets.0.model", box}}));
  const std::string other_digest =
      LoadScenarioText(kMinimal, "s.yaml", {{"targets.0.model", other}})
          .world.targets[0]
          .model_digest;

  // Another model named by an override: the pinned digest, the old model's,
  // goes with it.
  const Scenario moved = LoadScenarioText(resolved, "r.yaml", {{"targets.0.model", other}});
  EXPECT_EQ(moved.world.targets[0].model_digest, other_digest);
  // Unless an override gives the digest too: then it is checked.
  EXPECT_EQ(LoadScenarioText(resolved, "r.yaml",
                             {{"targets.0.model", other}, {"targets.0.model_digest", other_digest}})
                .world.targets[0]
                .model_digest,
            other_digest);
  std::string error = ModelLoadError(
      resolved, {{"targets.0.model", other}, {"targets.0.model_digest", std::string(32, 'a')}});
  EXPECT_NE(error.find("targets[0].model_digest: expected " + other_digest), std::string::npos)
      << error;

  // Not a digest; a digest for a box.
  error = ModelLoadError(kMinimal, {{"targets.0.model", box}, {"targets.0.model_digest", "abc"}});
  EXPECT_NE(error.find("targets[0].model_digest: expected a digest: 32 lowercase hexadecimal "
                       "digits"),
            std::string::npos)
      << error;
  error = ModelLoadError(kMinimal, {{"targets.1.model_digest", other_digest}});
  EXPECT_NE(error.find("targets[1].model_digest: expected no model_digest without a `model`"),
            std::string::npos)
      << error;
}

// The det.txt's digest goes likewise with the path an override replaces.
TEST(ModelDigest, ADetectionFilesDigestGoesWithThePathAnOverrideReplaces) {
  const fs::path dir = hcpf::testing::FreshDir("detection-digest-override");
  WriteTextFile((dir / "a.txt").string(), "1,-1,11,21,30,15,0.9\n");
  WriteTextFile((dir / "b.txt").string(), "2,-1,11,21,30,15,0.8\n");
  const std::vector<Override> file = {{"observation.source", "rendered"},
                                      {"observation.detector", "file"},
                                      {"observation.file.path", (dir / "a.txt").string()}};
  const std::string resolved = ToResolvedYaml(LoadScenarioText(kMinimal, "s.yaml", file));
  const Scenario b =
      LoadScenarioText(resolved, "r.yaml", {{"observation.file.path", (dir / "b.txt").string()}});
  EXPECT_EQ(b.observation.file.frames->at(1).size(), 1u);
  const std::string error =
      ModelLoadError(resolved, {{"observation.file.path", (dir / "b.txt").string()},
                                {"observation.file.digest", std::string(32, 'a')}});
  EXPECT_NE(error.find("observation.file.digest"), std::string::npos) << error;
}

}  // namespace
}  // namespace hcpf::scenarios
