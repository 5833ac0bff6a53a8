#include "logic/lua_sandbox.hpp"

#include <cmath>
#include <cstdlib>

#include <lua.hpp>

// Lua raises errors with longjmp: the functions it can unwind (everything below that runs inside
// lua_pcall) keep no object with a destructor in their frames.
namespace meter::engine::logic {
namespace {

constexpr std::size_t kMaxTextBytes = 256;  // a text output is a readout, not a document

LuaSandbox* self(lua_State* L) { return *static_cast<LuaSandbox**>(lua_getextraspace(L)); }

// The state's allocator: counts live bytes against the memory limit and, during a run (the
// chunk's first execution counts as one), the bytes grown against the per-run limit, which stops
// a loop copying big strings long before it could stall a frame. Once a run hits a limit every
// growth fails until the run ends, so a script that catches the error with pcall cannot go on.
void* sandbox_alloc(void* ud, void* ptr, std::size_t osize, std::size_t nsize) {
  auto* a = static_cast<LuaSandbox::Alloc*>(ud);
  const std::size_t old = ptr ? osize : 0;  // for a new block, osize is the object's type
  if (nsize == 0) {
    std::free(ptr);
    a->used -= old;
    return nullptr;
  }
  if (nsize <= old) {  // Lua relies on shrinking never failing: keep the block if realloc does
    void* p = std::realloc(ptr, nsize);
    a->used -= old - nsize;
    return p ? p : ptr;
  }
  const std::size_t grow = nsize - old;
  if (a->refused || a->used + grow > a->limit || (a->in_run && a->run_bytes + grow > a->run_limit)) {
    if (a->in_run) a->refused = true;
    return nullptr;
  }
  void* p = std::realloc(ptr, nsize);
  if (!p) return nullptr;
  a->used += grow;
  if (a->in_run) a->run_bytes += grow;
  if (a->used > a->peak) a->peak = a->used;
  return p;
}

// Every kHookStep instructions: remember the line, count, and past the limit raise an error on
// every following instruction (so an enclosing pcall in the script cannot swallow it for good).
// On every call: remember the caller's line, so a memory error inside a library function (which
// Lua raises without a message handler) still names the line that called it.
void script_hook(lua_State* L, lua_Debug* ar) {
  LuaSandbox* s = self(L);
  auto& r = s->current();
  if (ar->event == LUA_HOOKCALL || ar->event == LUA_HOOKTAILCALL) {
    lua_Debug caller;
    if (lua_getstack(L, 1, &caller) && lua_getinfo(L, "l", &caller) && caller.currentline > 0) r.line = caller.currentline;
    return;
  }
  if (lua_getinfo(L, "l", ar) && ar->currentline > 0) r.line = ar->currentline;
  r.instructions += r.instruction_limit ? 1 : LuaSandbox::kHookStep;
  if (!r.instruction_limit && r.instructions < s->script().limits.instructions) return;
  if (!r.instruction_limit) {
    r.instruction_limit = true;
    lua_sethook(L, script_hook, LUA_MASKCOUNT | LUA_MASKCALL, 1);
  }
  lua_pushfstring(L, "%s:%d: instruction limit (%d per run) exceeded", s->script().name.c_str(), r.line,
                  static_cast<int>(s->script().limits.instructions));
  lua_error(L);
}

// Runs at the point of a runtime error: the innermost Lua line, for messages whose text has none.
int message_handler(lua_State* L) {
  auto& r = self(L)->current();
  r.line = -1;
  lua_Debug ar;
  for (int level = 1; lua_getstack(L, level, &ar); ++level) {
    if (lua_getinfo(L, "l", &ar) && ar.currentline > 0) {
      r.line = ar.currentline;
      break;
    }
  }
  return 1;
}

// table.move, table.insert and table.remove shift elements one by one in C; over absent (nil)
// elements that neither allocates nor runs an instruction, so neither limit would see
// table.move({}, 1, 1e12, 2) or an insert into a table whose __len says 1e15. Bounded here: the
// wrapper checks the span (move: e - f, insert / remove: the length) and calls the original.
constexpr lua_Integer kMaxShift = 1 << 20;
int guarded_shift(lua_State* L) {
  const bool move = lua_toboolean(L, lua_upvalueindex(2)) != 0;
  lua_Integer span = 0;
  if (move) {
    const lua_Integer f = luaL_checkinteger(L, 2), e = luaL_checkinteger(L, 3);
    // In unsigned arithmetic: e - f of e.g. maxinteger and mininteger does not fit.
    const lua_Unsigned d = static_cast<lua_Unsigned>(e) - static_cast<lua_Unsigned>(f);
    span = e < f ? 0 : d >= static_cast<lua_Unsigned>(kMaxShift) ? kMaxShift : static_cast<lua_Integer>(d);
  } else {
    luaL_checktype(L, 1, LUA_TTABLE);
    span = luaL_len(L, 1);  // through __len, as the original reads it
  }
  if (span >= kMaxShift) return luaL_error(L, "table.%s over more than %d elements", move ? "move" : "insert/remove", static_cast<int>(kMaxShift));
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, n, LUA_MULTRET);
  return lua_gettop(L);
}

void open_library(lua_State* L, const char* name, lua_CFunction open, std::initializer_list<const char*> removed) {
  luaL_requiref(L, name, open, 1);
  for (const char* f : removed) {
    lua_pushnil(L);
    lua_setfield(L, -2, f);
  }
  lua_pop(L, 1);
}

const char* status_name(protocol::SignalStatus s) {
  switch (s) {
    case protocol::SignalStatus::Valid: return "valid";
    case protocol::SignalStatus::TimedOut: return "timed-out";
    case protocol::SignalStatus::Invalid: return "invalid";
    case protocol::SignalStatus::NotAvailable: return "not-available";
  }
  return "not-available";
}

void raw_set(lua_State* L, int table, const char* key) {  // value on top
  lua_pushstring(L, key);
  lua_insert(L, -2);
  lua_rawset(L, table < 0 ? table - 1 : table);
}

// The output on top of the stack, checked for its kind, into `out`. Raises a Lua error naming it.
void read_output(lua_State* L, const bridge::ScriptOutput& o, OutputValue& out) {
  using K = bridge::ScriptOutputKind;
  const int t = lua_type(L, -1);
  out = OutputValue{};
  if (t == LUA_TNIL) return;
  out.set = true;
  const char* name = o.name.c_str();
  auto finite = [&](int idx, const char* what) {
    if (lua_type(L, idx) != LUA_TNUMBER) luaL_error(L, "output %s: expected %s, got %s", name, what, luaL_typename(L, idx));
    const double v = lua_tonumber(L, idx);
    if (!std::isfinite(v)) luaL_error(L, "output %s: expected a finite number, got NaN or infinity", name);
    return v;
  };
  const int n = bridge::value_components(o.kind);
  if (o.kind == K::Visible) {
    if (t != LUA_TBOOLEAN) luaL_error(L, "output %s: expected true, false or nil, got %s", name, luaL_typename(L, -1));
    out.visible = lua_toboolean(L, -1) != 0;
  } else if (o.kind == K::Text) {
    if (t != LUA_TSTRING && t != LUA_TNUMBER) luaL_error(L, "output %s: expected a string or nil, got %s", name, luaL_typename(L, -1));
    std::size_t len = 0;
    const char* s = lua_tolstring(L, -1, &len);
    if (len > kMaxTextBytes) luaL_error(L, "output %s: a text of %d bytes (at most %d)", name, static_cast<int>(len), static_cast<int>(kMaxTextBytes));
    out.text.assign(s, len);
  } else if (n == 1) {
    out.numbers[0] = finite(-1, "a number or nil");
  } else {
    if (t != LUA_TTABLE) luaL_error(L, "output %s: expected a table of %d numbers or nil, got %s", name, n, luaL_typename(L, -1));
    for (int i = 1; i <= n; ++i) {
      const int et = lua_rawgeti(L, -1, i);
      if (i == 4 && et == LUA_TNIL) out.numbers[3] = 1.0;  // colour: alpha 1 when only rgb is given
      else out.numbers[static_cast<std::size_t>(i - 1)] = finite(-1, "a number in each component");
      lua_pop(L, 1);
    }
  }
}

}  // namespace

int LuaSandbox::protected_setup(lua_State* L) {
  LuaSandbox* s = self(L);
  open_library(L, LUA_GNAME, luaopen_base, {"dofile", "loadfile", "load", "collectgarbage", "print", "warn"});
  open_library(L, LUA_TABLIBNAME, luaopen_table, {});
  lua_getglobal(L, LUA_TABLIBNAME);
  for (const char* f : {"move", "insert", "remove"}) {
    lua_getfield(L, -1, f);
    lua_pushboolean(L, f[0] == 'm');
    lua_pushcclosure(L, guarded_shift, 2);
    lua_setfield(L, -2, f);
  }
  lua_pop(L, 1);
  // find / match / gmatch / gsub backtrack inside C, where no instruction count reaches them.
  open_library(L, LUA_STRLIBNAME, luaopen_string, {"dump", "find", "match", "gmatch", "gsub"});
  open_library(L, LUA_MATHLIBNAME, luaopen_math, {});
  open_library(L, LUA_UTF8LIBNAME, luaopen_utf8, {});
  lua_newtable(L);
  for (const auto& in : s->script_.inputs) {
    lua_newtable(L);
    raw_set(L, -2, in.name.c_str());
  }
  s->in_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  lua_newtable(L);
  s->out_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  // Mode "t": a precompiled (binary) chunk is refused, never loaded.
  const char* chunk = s->chunk_name_.c_str();
  if (luaL_loadbufferx(L, s->script_.code.data(), s->script_.code.size(), chunk, "t") != LUA_OK) lua_error(L);
  lua_call(L, 0, 0);
  lua_rawgeti(L, LUA_REGISTRYINDEX, LUA_RIDX_GLOBALS);
  lua_pushstring(L, "run");
  lua_rawget(L, -2);
  if (lua_type(L, -1) != LUA_TFUNCTION) luaL_error(L, "%s: the script defines no function run(IN, OUT)", s->script_.name.c_str());
  s->run_ref_ = luaL_ref(L, LUA_REGISTRYINDEX);
  return 0;
}

int LuaSandbox::protected_run(lua_State* L) {
  LuaSandbox* s = self(L);
  const auto& inputs = s->run_.inputs;
  lua_rawgeti(L, LUA_REGISTRYINDEX, s->in_ref_);
  const int in = lua_gettop(L);
  for (std::size_t i = 0; i < s->script_.inputs.size() && i < inputs.size(); ++i) {
    const InputValue& v = inputs[i];
    const char* name = s->script_.inputs[i].name.c_str();
    lua_pushstring(L, name);
    if (lua_rawget(L, in) != LUA_TTABLE) {  // the script replaced IN.<name>: a fresh one
      lua_pop(L, 1);
      lua_newtable(L);
      lua_pushvalue(L, -1);
      raw_set(L, in, name);
    }
    const bool valid = v.status == protocol::SignalStatus::Valid;
    if (!valid) lua_pushnil(L);
    else if (v.is_text) lua_pushlstring(L, v.text.data(), v.text.size());
    else if (v.is_integer) lua_pushinteger(L, static_cast<lua_Integer>(v.value));
    else lua_pushnumber(L, v.value);
    raw_set(L, -2, "value");
    lua_pushstring(L, status_name(v.status));
    raw_set(L, -2, "status");
    lua_pushboolean(L, valid);
    raw_set(L, -2, "valid");
    lua_pop(L, 1);
  }
  lua_rawgeti(L, LUA_REGISTRYINDEX, s->out_ref_);
  const int out = lua_gettop(L);
  lua_rawgeti(L, LUA_REGISTRYINDEX, s->run_ref_);
  lua_pushvalue(L, in);
  lua_pushvalue(L, out);
  lua_call(L, 2, 0);
  auto& values = *s->run_.outputs;
  for (std::size_t i = 0; i < s->script_.outputs.size(); ++i) {
    lua_pushstring(L, s->script_.outputs[i].name.c_str());
    lua_rawget(L, out);
    read_output(L, s->script_.outputs[i], values[i]);
    lua_pop(L, 1);
  }
  return 0;
}

LuaSandbox::LuaSandbox(const bridge::Script& script) : script_(script), chunk_name_("=" + script.name) {
  alloc_.limit = script.limits.memory_bytes;
  alloc_.run_limit = script.limits.run_alloc_bytes;
  L_ = lua_newstate(sandbox_alloc, &alloc_);
  if (!L_) {
    error_ = script.name + ": cannot create its Lua state within the memory limit";
    return;
  }
  *static_cast<LuaSandbox**>(lua_getextraspace(L_)) = this;
  if (!call_protected(protected_setup)) run_ref_ = -1;
}

LuaSandbox::~LuaSandbox() {
  // Finalizers a script left run here, still under the instruction hook.
  if (L_) lua_close(L_);
}

bool LuaSandbox::call_protected(int (*body)(lua_State*)) {
  alloc_.in_run = true;
  alloc_.run_bytes = 0;
  alloc_.refused = false;
  lua_sethook(L_, script_hook, LUA_MASKCOUNT | LUA_MASKCALL, kHookStep);  // also restarts the count
  const int top = lua_gettop(L_);
  lua_pushcfunction(L_, message_handler);
  lua_pushcfunction(L_, body);
  const int rc = lua_pcall(L_, 0, 0, top + 1);
  const bool ok = rc == LUA_OK && !alloc_.refused && !run_.instruction_limit;
  if (!ok) error_ = describe_failure(rc, rc != LUA_OK && lua_type(L_, -1) == LUA_TSTRING ? lua_tostring(L_, -1) : nullptr);
  lua_settop(L_, top);
  alloc_.in_run = false;
  alloc_.refused = false;
  return ok;
}

bool LuaSandbox::run(std::span<const InputValue> inputs, std::vector<OutputValue>& outputs) {
  if (broken()) return false;
  outputs.resize(script_.outputs.size());
  run_ = Run{inputs, &outputs, 0, false, -1};
  return call_protected(protected_run);
}

std::string LuaSandbox::describe_failure(int rc, const char* message) const {
  const std::string& name = script_.name;
  const std::string at = name + (run_.line > 0 ? ":" + std::to_string(run_.line) : "") + ": ";
  if (alloc_.refused || rc == LUA_ERRMEM) {
    return at + "memory limit exceeded (" + std::to_string(script_.limits.memory_bytes / 1024) + " KiB live, " +
           std::to_string(script_.limits.run_alloc_bytes / 1024) + " KiB allocated per run)";
  }
  if (run_.instruction_limit) {
    return at + "instruction limit (" + std::to_string(script_.limits.instructions) + " per run) exceeded";
  }
  if (!message) return at + "error (the error value is not a string)";
  const std::string m = message;
  if (m.rfind(name + ":", 0) == 0) return m;  // Lua's own "<chunk>:<line>: ..." position
  return at + m;
}

}  // namespace meter::engine::logic
