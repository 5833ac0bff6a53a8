// The scene-script sandbox: every way out of it refused, every bomb stopped by a limit, and the
// state still usable (and the process alive) afterwards. Without GL.
#include <gtest/gtest.h>

#include <lua.hpp>
#include <nlohmann/json.hpp>

#include "meter/config/lua_syntax.hpp"
#include "meter/engine/logic/scripts.hpp"
#include "script_scene.hpp"

using namespace meter::engine;
using meter::protocol::SignalStatus;
using meter::protocol::SignalTable;
using nlohmann::json;

namespace {

// Runs `body` as the body of run(IN, OUT) (line 2 of the chunk) with OUT.ok = true after it, and
// returns the error (empty when the run succeeded).
struct Outcome {
  std::string error;
  bool lamp_shown = false;
};
Outcome run_body(const std::string& body, const json& limits = json::object()) {
  json sc = {{"name", "box"},
             {"code", "function run(IN, OUT)\n" + body + "\nOUT.ok = true\nend"},
             {"inputs", {{"v", "Vehicle.Speed"}}},
             {"outputs", {{"ok", {{"property", "visible"}, {"node", "Lamp"}, {"failsafe", false}}}}}};
  if (!limits.empty()) sc["limits"] = limits;
  const Scene s = test::script_scene(json::array({sc}).dump());
  ScriptEngine eng(s);
  SignalTable values;
  values.set(meter::protocol::sig::kSpeed, {1.0, SignalStatus::Valid, ""});
  BindingOutputs out = resting_outputs(s);
  eng.update(values, true, out);
  Outcome o;
  o.error = eng.stats()[0].failed ? eng.stats()[0].last_error : "";
  o.lamp_shown = out.node_visible[0] == 1;
  return o;
}

}  // namespace

TEST(ScriptSandbox, TheOrdinaryLibrariesWork) {
  EXPECT_EQ(run_body("assert(math.floor(2.5) == 2 and string.format('%03d', 7) == '007' and #table.pack(1, 2) == 2)\n"
                     "assert(utf8.char(72, 105) == 'Hi' and ('abc'):upper() == 'ABC' and select('#', 1, 2, 3) == 3)\n"
                     "assert(pcall(error, 'x') == false and tostring(nil) == 'nil' and tonumber('12') == 12)")
                .error,
            "");
}

TEST(ScriptSandbox, NoWayToFilesProcessesModulesOrCode) {
  const test::LuaCase cases[] = {
      {"io.open('/etc/passwd')", "box:2: attempt to index a nil value (global 'io')"},
      {"os.execute('touch /tmp/meter_escaped')", "box:2: attempt to index a nil value (global 'os')"},
      {"require('os')", "box:2: attempt to call a nil value (global 'require')"},
      {"package.loadlib('libc.so.6', 'system')", "box:2: attempt to index a nil value (global 'package')"},
      {"debug.sethook()", "box:2: attempt to index a nil value (global 'debug')"},
      {"load('return 1')()", "box:2: attempt to call a nil value (global 'load')"},
      {"loadstring('return 1')()", "box:2: attempt to call a nil value (global 'loadstring')"},
      {"dofile('/etc/passwd')", "box:2: attempt to call a nil value (global 'dofile')"},
      {"loadfile('/etc/passwd')", "box:2: attempt to call a nil value (global 'loadfile')"},
      {"string.dump(run)", "box:2: attempt to call a nil value (field 'dump')"},
      {"collectgarbage('stop')", "box:2: attempt to call a nil value (global 'collectgarbage')"},
      {"print('x')", "box:2: attempt to call a nil value (global 'print')"},
      {"coroutine.wrap(function() end)()", "box:2: attempt to index a nil value (global 'coroutine')"},
      // Pattern matching backtracks in C, out of the instruction count's reach.
      {"string.find(string.rep('a', 30), string.rep('a*', 20) .. 'b')", "box:2: attempt to call a nil value (field 'find')"},
      {"('x'):gsub('x', 'y')", "box:2: attempt to call a nil value (method 'gsub')"},
      // The string metatable's __index is the sandboxed string table: no dump through it either.
      {"getmetatable('').__index.dump(run)", "box:2: attempt to call a nil value (field 'dump')"},
  };
  for (const auto& c : cases) EXPECT_EQ(run_body(c.code).error, c.error) << c.code;
}

TEST(ScriptSandbox, MetatableTricksOnTheEnvironmentReachNothing) {
  // An __index on _G answers every missing name: what comes back is the script's own value.
  EXPECT_EQ(run_body("setmetatable(_G, {__index = function(_, k) return k end})\n"
                     "assert(io == 'io' and rawget(_G, 'os') == nil and rawget(_G, 'load') == nil)\n"
                     "io.open('/etc/passwd')")
                .error,
            "box:4: attempt to call a nil value (field 'open')");
  // A metatable on IN or OUT does not run when the view reads or writes them (raw access).
  EXPECT_EQ(run_body("setmetatable(OUT, {__index = function() error('read through a metamethod') end})\n"
                     "setmetatable(IN.v, {__newindex = function() error('written through a metamethod') end})")
                .error,
            "");
  // Nothing from the C side is reachable through the registry either: debug is absent.
  EXPECT_EQ(run_body("local r = debug.getregistry()").error, "box:2: attempt to index a nil value (global 'debug')");
}

TEST(ScriptSandbox, BytecodeIsNeverLoaded) {
  // Real Lua 5.4 bytecode, made here with lua_dump.
  lua_State* L = luaL_newstate();
  ASSERT_EQ(luaL_loadstring(L, "function run(IN, OUT) OUT.ok = true end"), LUA_OK);
  std::string bytecode;
  lua_dump(L, [](lua_State*, const void* p, size_t n, void* ud) { static_cast<std::string*>(ud)->append(static_cast<const char*>(p), n); return 0; }, &bytecode, 0);
  lua_close(L);
  ASSERT_EQ(bytecode.substr(0, 4), "\x1bLua");
  const std::string why = meter::config::lua_syntax_error(bytecode, "box");
  EXPECT_EQ(why, "box: attempt to load a binary chunk (mode is 't')");
}

TEST(ScriptSandbox, MemoryBombsHitTheMemoryLimit) {
  const char* kLimit = "memory limit exceeded (256 KiB live, 4096 KiB allocated per run)";
  for (const char* body : {
           "local s = string.rep('x', 1000000000)",
           "local s = string.rep('x', 1000, ',')  for i = 1, 40 do s = s .. s end",
           "local t = {} for i = 1, 100000000 do t[i] = i end",
           "local t = {} for i = 1, 100000 do t[i] = 'line ' .. i end local s = table.concat(t, ',', 1, #t)",
       }) {
    const Outcome o = run_body(body);
    EXPECT_NE(o.error.find(kLimit), std::string::npos) << body << " -> " << o.error;
    EXPECT_NE(o.error.rfind("box", 0), std::string::npos) << o.error;
    EXPECT_FALSE(o.lamp_shown);  // failsafe
  }
  // Copies that stay under the live cap but would allocate 100 MB in one run: the per-run cap.
  const Outcome o = run_body("local s = string.rep('x', 100000) for i = 1, 1000 do local t = s .. i end");
  EXPECT_NE(o.error.find(kLimit), std::string::npos) << o.error;
  // Catching the memory error does not buy another attempt: the run is failed anyway.
  EXPECT_NE(run_body("for i = 1, 10 do pcall(string.rep, 'x', 1000000000) end").error.find(kLimit), std::string::npos);
}

TEST(ScriptSandbox, EndlessLoopsHitTheInstructionLimit) {
  const char* kLimit = "instruction limit (100000 per run) exceeded";
  EXPECT_EQ(run_body("while true do end").error, std::string("box:2: ") + kLimit);
  EXPECT_EQ(run_body("local n = 0\nrepeat n = n + 1 until n < 0").error, std::string("box:3: ") + kLimit);
  // Swallowing the limit's error with pcall does not help: every later instruction raises it.
  EXPECT_NE(run_body("while true do pcall(function() while true do end end) end").error.find(kLimit), std::string::npos);
  // A loop in a metamethod the script calls is counted too.
  EXPECT_NE(run_body("tostring(setmetatable({}, {__tostring = function() while true do end end}))").error.find(kLimit), std::string::npos);
  // A library loop in C that neither allocates nor runs an instruction: bounded on its own.
  EXPECT_EQ(run_body("table.move({}, 1, 1e12, 2)").error, "box:2: table.move over more than 1048576 elements");
  EXPECT_EQ(run_body("table.move({}, math.mininteger, math.maxinteger, 2)").error, "box:2: table.move over more than 1048576 elements");
  EXPECT_EQ(run_body("table.insert(setmetatable({}, {__len = function() return 1e15 end}), 1, 'x')").error,
            "box:2: table.insert/remove over more than 1048576 elements");
  EXPECT_EQ(run_body("table.remove(setmetatable({}, {__len = function() return 1e15 end}), 1)").error,
            "box:2: table.insert/remove over more than 1048576 elements");
  EXPECT_EQ(run_body("local t = table.move({1, 2, 3}, 1, 3, 2) table.insert(t, 1, 0) assert(table.remove(t) == 3 and t[1] == 0)").error, "");
  // The limit is the config's.
  EXPECT_NE(run_body("for i = 1, 20000 do end", {{"instructions", 10000}}).error.find("instruction limit (10000 per run)"), std::string::npos);
  EXPECT_EQ(run_body("for i = 1, 20000 do end").error, "");
}

TEST(ScriptSandbox, DeepRecursionIsStoppedByTheStackLimits) {
  // Lua recursion: the Lua stack grows until the memory limit (or Lua's own stack limit) stops it.
  const std::string lua_rec = run_body("local function f(n) return 1 + f(n + 1) end\nf(1)").error;
  EXPECT_TRUE(lua_rec.find("memory limit exceeded") != std::string::npos || lua_rec.find("stack overflow") != std::string::npos) << lua_rec;
  // Recursion through C (a metamethod calling itself): Lua's C-stack limit.
  const std::string c_rec = run_body("local t = setmetatable({}, {__index = function(t, k) return t[k] end})\nlocal x = t.x").error;
  EXPECT_NE(c_rec.find("stack overflow"), std::string::npos) << c_rec;
  // Through pcall, xpcall and tostring's __tostring: stopped the same way.
  const std::string p_rec = run_body("local function f() return select(2, pcall(f)) end\nerror(f())").error;
  EXPECT_NE(p_rec.find("box:"), std::string::npos) << p_rec;
  const std::string t_rec = run_body("local m = {} m.__tostring = function(x) return tostring(x) end\ntostring(setmetatable({}, m))").error;
  EXPECT_NE(t_rec.find("stack overflow"), std::string::npos) << t_rec;
}

TEST(ScriptSandbox, AFailedRunLeavesTheStateUsable) {
  // First run bombs, the next run (an input changed) works: the state is not left broken.
  json sc = {{"name", "again"},
             {"code", "function run(IN, OUT)\n if IN.v.value < 1 then local s = string.rep('x', 1e9) end\n OUT.ok = true\nend"},
             {"inputs", {{"v", "Vehicle.Speed"}}},
             {"outputs", {{"ok", {{"property", "visible"}, {"node", "Lamp"}, {"failsafe", false}}}}}};
  const Scene s = test::script_scene(json::array({sc}).dump());
  ScriptEngine eng(s);
  SignalTable values;
  BindingOutputs out = resting_outputs(s);
  values.set(meter::protocol::sig::kSpeed, {0.0, SignalStatus::Valid, ""});
  eng.update(values, true, out);
  EXPECT_TRUE(eng.stats()[0].failed);
  EXPECT_EQ(eng.stats()[0].last_error, "again:2: memory limit exceeded (256 KiB live, 4096 KiB allocated per run)");
  values.set(meter::protocol::sig::kSpeed, {5.0, SignalStatus::Valid, ""});
  out = resting_outputs(s);
  eng.update(values, true, out);
  EXPECT_FALSE(eng.stats()[0].failed) << eng.stats()[0].last_error;
  EXPECT_EQ(out.node_visible[0], 1);
  EXPECT_LE(eng.stats()[0].memory_peak_bytes, 256u * 1024u);
}

TEST(ScriptSandbox, ScriptsDoNotShareAState) {
  // One script vandalising its libraries and globals changes nothing in another.
  json a = {{"name", "vandal"},
            {"code", "string.upper = nil math = nil shared = 1 function run(IN, OUT) OUT.x = true end"},
            {"inputs", {{"v", "Vehicle.Speed"}}},
            {"outputs", {{"x", {{"property", "visible"}, {"node", "Lamp"}}}}}};
  json b = {{"name", "other"},
            {"code", "function run(IN, OUT) OUT.t = ('a'):upper() .. tostring(math.pi > 3) .. tostring(shared) end"},
            {"inputs", {{"v", "Vehicle.Speed"}}},
            {"outputs", {{"t", {{"property", "text"}, {"node", "Text_Gear"}}}}}};
  const Scene s = test::script_scene(json::array({a, b}).dump());
  ScriptEngine eng(s);
  SignalTable values;
  BindingOutputs out = resting_outputs(s);
  eng.update(values, true, out);
  ASSERT_FALSE(eng.stats()[1].failed) << eng.stats()[1].last_error;
  EXPECT_EQ(out.texts.at(0).text, "Atruenil");
}
