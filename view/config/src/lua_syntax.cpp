// A scene script compiled as Lua text without running it (meter/config/lua_syntax.hpp).
#include "meter/config/lua_syntax.hpp"

#include <lua.hpp>

namespace meter::config {

std::string lua_syntax_error(std::string_view code, const std::string& chunk_name) {
  lua_State* L = luaL_newstate();
  if (!L) return chunk_name + ": cannot create a Lua state to check the script";
  const std::string chunk = "=" + chunk_name;
  // Mode "t": a precompiled (binary) chunk is refused, never loaded.
  const int rc = luaL_loadbufferx(L, code.data(), code.size(), chunk.c_str(), "t");
  std::string why;
  if (rc != LUA_OK) {
    const char* m = lua_tostring(L, -1);
    why = m ? m : "the script does not compile";
    if (why.rfind(chunk_name + ":", 0) != 0) why = chunk_name + ": " + why;  // e.g. a binary chunk
  }
  lua_close(L);
  return why;
}

}  // namespace meter::config
