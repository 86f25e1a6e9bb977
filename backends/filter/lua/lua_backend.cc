// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter framework=lua: runs a Lua 5.4 script following NNStreamer's convention.
//
// model= is a .lua file, or (when model= names no existing file) the script text itself; the
// pieces tensor_filter split on ',' are joined back. The script defines
//   inputTensorsInfo  = { num = N, type = {'uint8', ...}, dim = {{3, 640, 480, 1}, ...} }
//   outputTensorsInfo = { ... the same ... }
//   function nnstreamer_invoke() ... end
// and reads/writes tensors inside nnstreamer_invoke() through input_tensor(i) and
// output_tensor(i) (i from 1), whose elements are indexed from 1: output_tensor(1)[k] = v.
// Element values are Lua integers for integer tensors and floats for float tensors; a float
// written into an integer tensor is truncated toward zero and saturated to the type's range
// (NaN gives 0). #tensor is the element count.
#include <lua.hpp>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "../common/backend_common.h"
#include "core/float16.h"
#include "nns_filter_backend.hh"

namespace {

constexpr const char *kTensorMeta = "nnstreamer.lua_tensor";

struct View {
  void *data = nullptr;
  size_t size = 0;
  tensor_type type = _NNS_END;
};

template <typename T>
T saturate(lua_State *L, int idx) {
  if (lua_isinteger(L, idx)) {
    lua_Integer v = lua_tointeger(L, idx);
    if constexpr (std::is_unsigned_v<T>) {
      if (v < 0) return 0;
      if (static_cast<unsigned long long>(v) > std::numeric_limits<T>::max())
        return std::numeric_limits<T>::max();
    } else {
      if (v < static_cast<lua_Integer>(std::numeric_limits<T>::min()))
        return std::numeric_limits<T>::min();
      if (v > static_cast<lua_Integer>(std::numeric_limits<T>::max()))
        return std::numeric_limits<T>::max();
    }
    return static_cast<T>(v);
  }
  double d = luaL_checknumber(L, idx);
  if (std::isnan(d)) return 0;
  d = std::trunc(d);
  if (d <= static_cast<double>(std::numeric_limits<T>::min())) return std::numeric_limits<T>::min();
  if (d >= static_cast<double>(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
  return static_cast<T>(d);
}

class LuaBackend;

// The userdata behind input_tensor(i) / output_tensor(i).
struct TensorRef {
  LuaBackend *owner;
  bool output;
  int index;  // 0-based
};

class LuaBackend final : public nns::FilterBackend {
 public:
  explicit LuaBackend(const nns_filter_props &p) {
    if (p.num_models < 1 || !p.model_files || !p.model_files[0])
      throw nns::FilterError("framework=lua needs model=<script.lua> or model=<script text>");
    L_ = luaL_newstate();
    if (!L_) throw nns::FilterError("lua: cannot create a Lua state (out of memory)");
    try {
      setup(p);
    } catch (...) {
      lua_close(L_);
      throw;
    }
  }
  ~LuaBackend() override { lua_close(L_); }

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    in = in_;
    out = out_;
    return true;
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    bind(ins_, in_, in, num_in);
    bind(outs_, out_, out, num_out);
    lua_getglobal(L_, "nnstreamer_invoke");
    int rc = lua_pcall(L_, 0, 0, 0);
    ins_.clear();
    outs_.clear();
    if (rc != LUA_OK) {
      std::string msg = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "(no message)";
      lua_pop(L_, 1);
      throw nns::FilterError("lua: nnstreamer_invoke() failed: " + msg);
    }
  }

  // Lua C functions.
  static int l_input(lua_State *L) { return push_ref(L, false); }
  static int l_output(lua_State *L) { return push_ref(L, true); }
  static int l_index(lua_State *L) {
    View &v = element(L);
    lua_Integer k = luaL_checkinteger(L, 2) - 1;
    const char *p = static_cast<const char *>(v.data) + k * nns::backend::type_size(v.type);
    switch (v.type) {
      case _NNS_INT8:
        lua_pushinteger(L, *reinterpret_cast<const int8_t *>(p));
        break;
      case _NNS_UINT8:
        lua_pushinteger(L, *reinterpret_cast<const uint8_t *>(p));
        break;
      case _NNS_INT16:
        lua_pushinteger(L, *reinterpret_cast<const int16_t *>(p));
        break;
      case _NNS_UINT16:
        lua_pushinteger(L, *reinterpret_cast<const uint16_t *>(p));
        break;
      case _NNS_INT32:
        lua_pushinteger(L, *reinterpret_cast<const int32_t *>(p));
        break;
      case _NNS_UINT32:
        lua_pushinteger(L, *reinterpret_cast<const uint32_t *>(p));
        break;
      case _NNS_INT64:
        lua_pushinteger(L, *reinterpret_cast<const int64_t *>(p));
        break;
      case _NNS_UINT64:
        lua_pushinteger(L, static_cast<lua_Integer>(*reinterpret_cast<const uint64_t *>(p)));
        break;
      case _NNS_FLOAT16: {
        uint16_t h;
        std::memcpy(&h, p, 2);
        lua_pushnumber(L, nns::half_to_float(h));
        break;
      }
      case _NNS_FLOAT32:
        lua_pushnumber(L, *reinterpret_cast<const float *>(p));
        break;
      case _NNS_FLOAT64:
        lua_pushnumber(L, *reinterpret_cast<const double *>(p));
        break;
      default:
        return luaL_error(L, "tensor of unknown type");
    }
    return 1;
  }
  static int l_newindex(lua_State *L) {
    auto *r = static_cast<TensorRef *>(luaL_checkudata(L, 1, kTensorMeta));
    if (!r->output)
      return luaL_error(L, "input_tensor(%d) is read-only; write into output_tensor()",
                        r->index + 1);
    View &v = element(L);
    lua_Integer k = luaL_checkinteger(L, 2) - 1;
    char *p = static_cast<char *>(v.data) + k * nns::backend::type_size(v.type);
    switch (v.type) {
      case _NNS_INT8:
        *reinterpret_cast<int8_t *>(p) = saturate<int8_t>(L, 3);
        break;
      case _NNS_UINT8:
        *reinterpret_cast<uint8_t *>(p) = saturate<uint8_t>(L, 3);
        break;
      case _NNS_INT16:
        *reinterpret_cast<int16_t *>(p) = saturate<int16_t>(L, 3);
        break;
      case _NNS_UINT16:
        *reinterpret_cast<uint16_t *>(p) = saturate<uint16_t>(L, 3);
        break;
      case _NNS_INT32:
        *reinterpret_cast<int32_t *>(p) = saturate<int32_t>(L, 3);
        break;
      case _NNS_UINT32:
        *reinterpret_cast<uint32_t *>(p) = saturate<uint32_t>(L, 3);
        break;
      case _NNS_INT64:
        *reinterpret_cast<int64_t *>(p) = saturate<int64_t>(L, 3);
        break;
      case _NNS_UINT64:
        *reinterpret_cast<uint64_t *>(p) = saturate<uint64_t>(L, 3);
        break;
      case _NNS_FLOAT16: {
        uint16_t h = nns::float_to_half(static_cast<float>(luaL_checknumber(L, 3)));
        std::memcpy(p, &h, 2);
        break;
      }
      case _NNS_FLOAT32:
        *reinterpret_cast<float *>(p) = static_cast<float>(luaL_checknumber(L, 3));
        break;
      case _NNS_FLOAT64:
        *reinterpret_cast<double *>(p) = luaL_checknumber(L, 3);
        break;
      default:
        return luaL_error(L, "tensor of unknown type");
    }
    return 0;
  }
  static int l_len(lua_State *L) {
    auto *r = static_cast<TensorRef *>(luaL_checkudata(L, 1, kTensorMeta));
    View *v = r->owner->view(L, *r);
    lua_pushinteger(L, static_cast<lua_Integer>(v->size / nns::backend::type_size(v->type)));
    return 1;
  }

 private:
  void setup(const nns_filter_props &p) {
    luaL_openlibs(L_);
    lua_pushlightuserdata(L_, this);
    lua_setfield(L_, LUA_REGISTRYINDEX, "nnstreamer.backend");
    luaL_newmetatable(L_, kTensorMeta);
    const luaL_Reg meta[] = {
        {"__index", l_index}, {"__newindex", l_newindex}, {"__len", l_len}, {nullptr, nullptr}};
    luaL_setfuncs(L_, meta, 0);
    lua_pop(L_, 1);
    lua_register(L_, "input_tensor", l_input);
    lua_register(L_, "output_tensor", l_output);

    std::string first = p.model_files[0];
    struct stat st;
    int rc;
    if (::stat(first.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
      rc = luaL_loadfilex(L_, first.c_str(), "t");
    } else {
      std::string script;
      for (uint32_t i = 0; i < p.num_models && p.model_files[i]; ++i)
        script += (i ? "," : "") + std::string(p.model_files[i]);
      rc = luaL_loadbufferx(L_, script.data(), script.size(), "=inline script", "t");
    }
    if (rc == LUA_OK) rc = lua_pcall(L_, 0, 0, 0);
    if (rc != LUA_OK) {
      std::string msg = lua_tostring(L_, -1) ? lua_tostring(L_, -1) : "(no message)";
      throw nns::FilterError("lua: cannot run the script: " + msg);
    }
    read_info("inputTensorsInfo", in_);
    read_info("outputTensorsInfo", out_);
    lua_getglobal(L_, "nnstreamer_invoke");
    bool fn = lua_isfunction(L_, -1);
    lua_pop(L_, 1);
    if (!fn) throw nns::FilterError("lua: the script defines no function nnstreamer_invoke()");
  }

  // inputTensorsInfo / outputTensorsInfo -> desc; throws naming the variable and field.
  void read_info(const char *var, nns_tensors_desc &d) {
    std::memset(&d, 0, sizeof d);
    auto bad = [&](const std::string &what) {
      lua_settop(L_, 0);
      throw nns::FilterError(std::string("lua: ") + var + ": " + what +
                             " (expected {num = N, type = {'uint8', ...}, dim = {{3, 224, 224, "
                             "1}, ...}})");
    };
    if (lua_getglobal(L_, var) != LUA_TTABLE) bad("the script does not define this table");
    lua_getfield(L_, -1, "num");
    int isnum = 0;
    lua_Integer num = lua_tointegerx(L_, -1, &isnum);
    lua_pop(L_, 1);
    if (!isnum || num < 1 || num > NNS_TENSOR_SIZE_LIMIT)
      bad("num must be an integer from 1 to " + std::to_string(NNS_TENSOR_SIZE_LIMIT));
    d.num_tensors = static_cast<uint32_t>(num);
    if (lua_getfield(L_, -1, "type") != LUA_TTABLE) bad("type is not a table");
    for (lua_Integer i = 1; i <= num; ++i) {
      lua_geti(L_, -1, i);
      const char *s = lua_tostring(L_, -1);
      std::string t = s ? s : "";
      lua_pop(L_, 1);
      uint32_t found = _NNS_END;
      for (uint32_t k = 0; k < _NNS_END; ++k)
        if (strcasecmp(t.c_str(), nns::backend::type_name(k)) == 0) found = k;
      if (found == _NNS_END)
        bad("type[" + std::to_string(i) + "] '" + t + "' is not a tensor type");
      d.tensors[i - 1].type = found;
    }
    lua_pop(L_, 1);
    if (lua_getfield(L_, -1, "dim") != LUA_TTABLE) bad("dim is not a table");
    for (lua_Integer i = 1; i <= num; ++i) {
      if (lua_geti(L_, -1, i) != LUA_TTABLE) bad("dim[" + std::to_string(i) + "] is not a table");
      lua_Integer rank = luaL_len(L_, -1);
      if (rank < 1 || rank > NNS_TENSOR_RANK_LIMIT)
        bad("dim[" + std::to_string(i) + "] must have 1 to " +
            std::to_string(NNS_TENSOR_RANK_LIMIT) + " entries");
      for (lua_Integer k = 1; k <= rank; ++k) {
        lua_geti(L_, -1, k);
        lua_Integer v = lua_tointegerx(L_, -1, &isnum);
        lua_pop(L_, 1);
        if (!isnum || v < 1 || v > std::numeric_limits<uint32_t>::max())
          bad("dim[" + std::to_string(i) + "][" + std::to_string(k) +
              "] must be a positive integer");
        d.tensors[i - 1].dims[k - 1] = static_cast<uint32_t>(v);
      }
      lua_pop(L_, 1);
    }
    lua_settop(L_, 0);
  }

  static void bind(std::vector<View> &views, const nns_tensors_desc &d, const GstTensorMemory *m,
                   uint32_t n) {
    views.assign(n, View{});
    for (uint32_t i = 0; i < n && i < d.num_tensors; ++i)
      views[i] = View{m[i].data, m[i].size, static_cast<tensor_type>(d.tensors[i].type)};
  }

  static LuaBackend *self(lua_State *L) {
    lua_getfield(L, LUA_REGISTRYINDEX, "nnstreamer.backend");
    auto *b = static_cast<LuaBackend *>(lua_touserdata(L, -1));
    lua_pop(L, 1);
    return b;
  }

  static int push_ref(lua_State *L, bool output) {
    lua_Integer i = luaL_checkinteger(L, 1);
    LuaBackend *b = self(L);
    auto &views = output ? b->outs_ : b->ins_;
    if (views.empty())
      return luaL_error(L, "%s() is only available inside nnstreamer_invoke()",
                        output ? "output_tensor" : "input_tensor");
    if (i < 1 || i > static_cast<lua_Integer>(views.size()))
      return luaL_error(L, "%s(%d): there are %d tensors (1..%d)",
                        output ? "output_tensor" : "input_tensor", static_cast<int>(i),
                        static_cast<int>(views.size()), static_cast<int>(views.size()));
    auto *r = static_cast<TensorRef *>(lua_newuserdatauv(L, sizeof(TensorRef), 0));
    *r = TensorRef{b, output, static_cast<int>(i - 1)};
    luaL_setmetatable(L, kTensorMeta);
    return 1;
  }

  View *view(lua_State *L, const TensorRef &r) {
    auto &views = r.output ? outs_ : ins_;
    if (r.index >= static_cast<int>(views.size()))
      luaL_error(L, "%s(%d) used outside nnstreamer_invoke()",
                 r.output ? "output_tensor" : "input_tensor", r.index + 1);
    return &views[r.index];
  }

  // The tensor of argument 1 with the element index of argument 2 checked.
  static View &element(lua_State *L) {
    auto *r = static_cast<TensorRef *>(luaL_checkudata(L, 1, kTensorMeta));
    View *v = r->owner->view(L, *r);
    lua_Integer k = luaL_checkinteger(L, 2);
    lua_Integer n = static_cast<lua_Integer>(v->size / nns::backend::type_size(v->type));
    if (k < 1 || k > n)
      luaL_error(L, "%s(%d)[%d]: index out of range (1..%d)",
                 r->output ? "output_tensor" : "input_tensor", r->index + 1, static_cast<int>(k),
                 static_cast<int>(n));
    return *v;
  }

  lua_State *L_ = nullptr;
  nns_tensors_desc in_{}, out_{};
  std::vector<View> ins_, outs_;  // non-empty only during nnstreamer_invoke()
};

const char *const kExt[] = {".lua", nullptr};

}  // namespace

NNS_FILTER_BACKEND_EXPORT(LuaBackend, "lua", NNS_FILTER_FLAG_RUN_WITHOUT_MODEL, kExt)
