// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/trainer/trainer_registry.h"

#include <cstring>

GST_DEBUG_CATEGORY_STATIC(nns_trainer_registry_debug);
#define GST_CAT_DEFAULT nns_trainer_registry_debug

namespace nns::gst {

namespace {

// The name getFrameworkInfo gives, kept per table (the registry reads it through name_of).
const char *trainer_name_of(const void *t) {
  auto *fw = static_cast<const GstTensorTrainerFramework *>(t);
  GstTensorTrainerFrameworkInfo info{};
  GstTensorTrainerProperties prop;
  std::memset(&prop, 0, sizeof prop);
  if (!fw || !fw->getFrameworkInfo || fw->getFrameworkInfo(fw, &prop, nullptr, &info) != 0)
    return nullptr;
  return info.name;
}

std::string check_trainer(const void *t) {
  auto *fw = static_cast<const GstTensorTrainerFramework *>(t);
  if (!fw) return "rejected: no table";
  if ((fw->version >> 32) != (GST_TENSOR_TRAINER_FRAMEWORK_BASE >> 32) ||
      ((fw->version >> 16) & 0xFFFF) != 1) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "rejected: version 0x%016llx is not 0x%016llx (V1)",
                  static_cast<unsigned long long>(fw->version),
                  static_cast<unsigned long long>(GST_TENSOR_TRAINER_FRAMEWORK_V1));
    return buf;
  }
  const char *name = trainer_name_of(fw);
  if (!name || !*name) return "rejected: getFrameworkInfo gives no name";
  if (!fw->create || !fw->destroy || !fw->start || !fw->push_data || !fw->getStatus)
    return "'" + std::string(name) +
           "' rejected: create, destroy, start, push_data, getStatus and getFrameworkInfo are "
           "mandatory";
  return {};
}

}  // namespace

std::string trainer_name(const GstTensorTrainerFramework *fw) {
  const char *n = trainer_name_of(fw);
  return n ? n : "";
}

TrainerRegistry::TrainerRegistry()
    : reg_({SubpluginKind::kTrainer, "trainer", "nnstreamer_trainer_subplugin", trainer_name_of,
            check_trainer, reinterpret_cast<void *>(&nnstreamer_trainer_probe),
            &nns_trainer_registry_debug}) {}

TrainerRegistry &TrainerRegistry::instance() {
  static TrainerRegistry *r = [] {
    GST_DEBUG_CATEGORY_INIT(nns_trainer_registry_debug, "nns_trainer_registry", 0,
                            "tensor_trainer sub-plugin registry");
    return new TrainerRegistry();
  }();
  return *r;
}

bool TrainerRegistry::add(const GstTensorTrainerFramework *fw) {
  return reg_.add(fw);
}
bool TrainerRegistry::remove(std::string_view name) {
  return reg_.remove(name);
}
const GstTensorTrainerFramework *TrainerRegistry::find(std::string_view name) {
  return static_cast<const GstTensorTrainerFramework *>(reg_.find(name));
}
std::vector<std::string> TrainerRegistry::names() {
  return reg_.names();
}
std::string TrainerRegistry::load_error(std::string_view name) {
  return reg_.load_error(name);
}
std::string TrainerRegistry::last_error(const GstTensorTrainerFramework *fw) {
  auto fn =
      reinterpret_cast<const char *(*)()>(reg_.file_symbol(fw, "nns_trainer_subplugin_last_error"));
  const char *e = fn ? fn() : nullptr;
  return e ? e : "";
}

}  // namespace nns::gst

extern "C" {

int nnstreamer_trainer_probe(GstTensorTrainerFramework *ttsp) {
  return nns::gst::TrainerRegistry::instance().add(ttsp) ? TRUE : FALSE;
}

int nnstreamer_trainer_exit(GstTensorTrainerFramework *ttsp) {
  const std::string name = nns::gst::trainer_name(ttsp);
  return !name.empty() && nns::gst::TrainerRegistry::instance().remove(name) ? TRUE : FALSE;
}

}  // extern "C"
