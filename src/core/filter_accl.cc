// SPDX-License-Identifier: LGPL-2.1-only
#include "core/filter_accl.h"

#include <strings.h>

#include <cstring>

#if defined(__aarch64__) || defined(__arm__)
#include <asm/hwcap.h>
#include <sys/auxv.h>
#endif

namespace nns::accl {
namespace {

struct Named {
  accl_hw hw;
  const char *name;
};

// In NNStreamer's order: the first entry of a value gives its name.
constexpr Named kNames[] = {
    {ACCL_NONE, ACCL_NONE_STR},
    {ACCL_DEFAULT, ACCL_DEFAULT_STR},
    {ACCL_AUTO, ACCL_AUTO_STR},
    {ACCL_CPU, ACCL_CPU_STR},
#if defined(__aarch64__) || defined(__arm__)
    {ACCL_CPU_NEON, ACCL_CPU_NEON_STR},
#endif
    {ACCL_CPU_SIMD, ACCL_CPU_SIMD_STR},
    {ACCL_GPU, ACCL_GPU_STR},
    {ACCL_NPU, ACCL_NPU_STR},
    {ACCL_NPU_MOVIDIUS, ACCL_NPU_MOVIDIUS_STR},
    {ACCL_NPU_EDGE_TPU, ACCL_NPU_EDGE_TPU_STR},
    {ACCL_NPU_VIVANTE, ACCL_NPU_VIVANTE_STR},
    {ACCL_NPU_SRCN, ACCL_NPU_SRCN_STR},
    {ACCL_NPU_SLSI, ACCL_NPU_SLSI_STR},
    {ACCL_NPU_SR, ACCL_NPU_SR_STR},
};

bool neon_available() {
#if defined(__aarch64__)
  return (getauxval(AT_HWCAP) & HWCAP_ASIMD) != 0;
#elif defined(__arm__)
  return (getauxval(AT_HWCAP) & HWCAP_NEON) != 0;
#else
  return true;  // NNStreamer filters cpu.neon out on Arm only
#endif
}

}  // namespace

accl_hw type_of(const char *name) {
  if (!name) return ACCL_NONE;
  for (const Named &n : kNames)
    if (std::strcmp(n.name, name) == 0) return n.hw;
  return ACCL_NONE;
}

const char *name_of(accl_hw hw) {
  for (const Named &n : kNames)
    if (n.hw == hw) return n.name;
  return ACCL_NONE_STR;
}

bool usable_here(const char *name) {
  static constexpr std::size_t kNeonLen = sizeof ACCL_CPU_NEON_STR - 1;
  return !(name && strncasecmp(name, ACCL_CPU_NEON_STR, kNeonLen) == 0 && !neon_available());
}

std::vector<accl_hw> match_all(const char *accelerators,
                               const std::vector<std::string> &supported) {
  if (!accelerators) return {ACCL_DEFAULT};
  if (supported.empty() || strncasecmp(accelerators, "true", 4) != 0) return {ACCL_NONE};
  std::vector<accl_hw> out;
  const std::size_t len = std::strlen(accelerators);
  std::size_t pos = 0;
  while (pos < len) {
    // The first supported name at this position, unless a '!' negates it.
    const std::string *hit = nullptr;
    if (pos == 0 || accelerators[pos - 1] != '!')
      for (const std::string &s : supported)
        if (!s.empty() && s.size() <= len - pos &&
            strncasecmp(accelerators + pos, s.c_str(), s.size()) == 0) {
          hit = &s;
          break;
        }
    if (!hit) {
      ++pos;
      continue;
    }
    // Kept only when spelled exactly as a known name ("GPU" is matched, then dropped).
    std::string word(accelerators + pos, hit->size());
    accl_hw hw = type_of(word.c_str());
    if (hw != ACCL_NONE || word == ACCL_NONE_STR) out.push_back(hw);
    pos += hit->size();
  }
  if (out.empty()) out.push_back(ACCL_AUTO);
  return out;
}

accl_hw parse(const char *accelerators, const char *const *supported, const char *auto_accl,
              const char *default_accl) {
  if (!supported || !supported[0]) return ACCL_NONE;
  std::vector<std::string> sup;
  for (const char *const *s = supported; *s; ++s)
    if (usable_here(*s)) sup.emplace_back(*s);
  if (sup.empty()) return ACCL_NONE;
  const std::string first = sup.front();
  const char *def = default_accl && usable_here(default_accl) ? default_accl : first.c_str();
  const char *aut = auto_accl && usable_here(auto_accl) ? auto_accl : first.c_str();
  sup.emplace_back(ACCL_AUTO_STR);
  sup.emplace_back(ACCL_DEFAULT_STR);
  accl_hw hw = match_all(accelerators, sup).front();
  if (hw == ACCL_AUTO) return type_of(aut);
  if (hw == ACCL_DEFAULT) return type_of(def);
  return hw;
}

}  // namespace nns::accl
