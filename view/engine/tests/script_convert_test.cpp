// Scene scripts at conversion: every error names the config file, the script and (for Lua) the
// line; a script file next to the config travels inlined in the package. Without GL.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <lua.hpp>
#include <nlohmann/json.hpp>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const char* kRun = "function run(IN, OUT) OUT.lamp = IN.v.valid end";

json lamp_script(json code_or_file) {
  json s = {{"name", "lamp"},
            {"inputs", {{"v", "Vehicle.Speed"}}},
            {"outputs", {{"lamp", {{"property", "visible"}, {"node", "TT_ABS"}}}}}};
  s.update(code_or_file);
  return s;
}

// The dial's config with `scripts`, written as dir/dial.scene.json; returns its path.
std::string write_config(const std::string& dir, const json& scripts) {
  json c = json::parse(test::dial_config_json());
  c["scripts"] = scripts;
  const std::string path = dir + "/dial.scene.json";
  std::ofstream(path) << c.dump(2);
  return path;
}

void write_file(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// The message of converting the dial with `scripts` in its config ("" when it converts).
std::string convert_error(const std::string& name, const json& scripts, const std::function<void(const std::string&)>& prepare = {}) {
  const std::string dir = test::scratch_dir(name);
  if (prepare) prepare(dir);
  try {
    const std::string config = write_config(dir, scripts);
    convert::convert_gltf(test::write_dial_scene(dir), meter::config::load_scene_config(config), convert::ConvertOptions{false});
  } catch (const std::exception& e) {
    return std::string(e.what()).substr(e.what()[0] == '/' ? dir.size() + 1 : 0);  // relative to the scratch dir
  }
  return "";
}

}  // namespace

TEST(ScriptConversion, ErrorsNameTheConfigFileTheScriptAndTheLine) {
  struct Case {
    json scripts;
    const char* error;
  } cases[] = {
      {json::array({lamp_script({{"code", "function run(IN, OUT)\n  if IN.v.valid OUT.lamp = true end\nend"}})}),
       "dial.scene.json: $.scripts[0].code: lamp:2: 'then' expected near 'OUT'"},
      {json::array({lamp_script({{"code", "local x = 1"}})}),
       "dial.scene.json: $.scripts[0].code: lamp: the script defines no function run(IN, OUT)"},
      {json::array({lamp_script({{"code", "function run() end\nlocal t = nil\nlocal x = t.field"}})}),
       "dial.scene.json: $.scripts[0].code: lamp:3: attempt to index a nil value (local 't')"},
      {json::array({lamp_script({{"code", "while true do end\nfunction run() end"}})}),
       "dial.scene.json: $.scripts[0].code: lamp:1: instruction limit (100000 per run) exceeded"},
      {json::array({lamp_script({{"code", kRun}, {"inputs", {{"v", "Vehicle.Nope"}}}})}),
       "dial.scene.json: $.scripts[0].inputs.v: \"Vehicle.Nope\" is not in the signal catalog"},
      {json::array({lamp_script({{"code", kRun}, {"outputs", {{"lamp", {{"property", "visible"}, {"node", "Nope"}}}}}})}),
       "dial.scene.json: $.scripts[0] (lamp).outputs.lamp.node: no node named \"Nope\" in "},
      {json::array({lamp_script({{"code", kRun}, {"outputs", {{"g", {{"property", "emissive"}, {"material", "Nope"}}}}}})}),
       "dial.scene.json: $.scripts[0] (lamp).outputs.g.material: no material named \"Nope\" in "},
      {json::array({lamp_script({{"code", kRun}, {"outputs", {{"m", {{"property", "morph"}, {"node", "FuelBar"}, {"target", 3}}}}}})}),
       "dial.scene.json: $.scripts[0] (lamp).outputs.m.target: node \"FuelBar\" has no morph target 3 in "},
      {json::array({lamp_script({{"code", kRun}, {"outputs", {{"lamp", {{"property", "glow"}, {"node", "TT_ABS"}}}}}})}),
       "dial.scene.json: $.scripts[0].outputs.lamp.property: unknown property \"glow\""},
      {json::array({lamp_script({{"code", kRun}}), lamp_script({{"code", kRun}, {"name", "again"}})}),
       "dial.scene.json: $.scripts[1].outputs.lamp: the visible of TT_ABS is already set by lamp.lamp (one writer per property)"},
      {json::array({lamp_script({{"code", kRun}, {"file", "x.lua"}})}),
       "dial.scene.json: $.scripts[0] (lamp): expected exactly one of \"code\""},
      {json::array({lamp_script({{"file", "logic/missing.lua"}})}), "dial.scene.json: $.scripts[0].file: cannot open script file "},
      {json::array({lamp_script({{"code", kRun}, {"limits", {{"memory_kb", 1}}}})}),
       "dial.scene.json: $.scripts[0].limits.memory_kb: expected an integer 64..65536"},
  };
  for (const auto& c : cases) {
    const std::string e = convert_error("script_convert_errors", c.scripts);
    EXPECT_EQ(e.substr(0, std::string(c.error).size()), c.error) << c.scripts.dump();
  }
}

TEST(ScriptConversion, AScriptFileIsCheckedWithItsOwnLines) {
  const std::string e = convert_error("script_convert_file_error", json::array({lamp_script({{"file", "logic/lamp.lua"}})}),
                                      [](const std::string& dir) {
                                        write_file(dir + "/logic/lamp.lua", "-- lamp\nfunction run(IN, OUT)\n  OUT.lamp = = true\nend\n");
                                      });
  EXPECT_EQ(e, "dial.scene.json: $.scripts[0].file (logic/lamp.lua): lamp:3: unexpected symbol near '='");
}

TEST(ScriptConversion, BytecodeInAScriptFileIsRefused) {
  const std::string e = convert_error("script_convert_bytecode", json::array({lamp_script({{"file", "lamp.luac"}})}),
                                      [](const std::string& dir) {
                                        lua_State* L = luaL_newstate();
                                        luaL_loadstring(L, kRun);
                                        std::string bytes;
                                        lua_dump(L, [](lua_State*, const void* p, size_t n, void* ud) {
                                          static_cast<std::string*>(ud)->append(static_cast<const char*>(p), n);
                                          return 0;
                                        }, &bytes, 0);
                                        lua_close(L);
                                        write_file(dir + "/lamp.luac", bytes);
                                      });
  EXPECT_EQ(e, "dial.scene.json: $.scripts[0].file (lamp.luac): lamp: attempt to load a binary chunk (mode is 't')");
}

TEST(ScriptConversion, AScriptFileTravelsInlinedInThePackage) {
  const std::string dir = test::scratch_dir("script_convert_inline");
  const std::string code = "-- shift light\nfunction run(IN, OUT)\n  OUT.lamp = IN.v.valid\nend\n";
  write_file(dir + "/logic/lamp.lua", code);
  const auto config = meter::config::load_scene_config(write_config(dir, json::array({lamp_script({{"file", "logic/lamp.lua"}})})));
  ASSERT_EQ(config.scripts.size(), 1u);
  EXPECT_EQ(config.scripts[0].code, code);
  const json stored = json::parse(config.source_json);
  EXPECT_FALSE(stored["scripts"][0].contains("file"));
  EXPECT_EQ(stored["scripts"][0]["code"], code);
  EXPECT_EQ(stored["scripts"][0]["inlined_from"], "logic/lamp.lua");
  auto result = convert::convert_gltf(test::write_dial_scene(dir), config, convert::ConvertOptions{false});
  const std::string package = dir + "/dial.msp";
  convert::write_package(result.scene, package);
  fs::remove(dir + "/logic/lamp.lua");  // the package alone carries it
  const Scene back = read_package(package);
  ASSERT_EQ(back.config.scripts.size(), 1u);
  EXPECT_EQ(back.config.scripts[0].code, code);
  EXPECT_EQ(back.config.scripts[0].file, "logic/lamp.lua");
  EXPECT_EQ(back.config.scripts[0].outputs[0].target, "TT_ABS");
}
