// A MuJoCo model from an MJCF text held in memory (through MuJoCo's virtual file system), for
// both MuJoCo runners (mujoco_runner.cc: free bodies; contacts_mujoco.cc: contacts).
#pragma once

#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

namespace bench {

// The compiled model, or an exception with MuJoCo's message. The caller owns it (mj_deleteModel).
inline mjModel* loadMujocoModel(const std::string& xml) {
  std::unique_ptr<mjVFS> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), "model.xml", static_cast<int>(xml.size())) != 0)
    throw std::runtime_error("mj_makeEmptyFileVFS failed");
  const int idx = mj_findFileVFS(vfs.get(), "model.xml");
  std::memcpy(vfs->filedata[idx], xml.data(), xml.size());
  char err[1000] = "";
  mjModel* m = mj_loadXML("model.xml", vfs.get(), err, sizeof err);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("mj_loadXML: ") + err);
  return m;
}

}  // namespace bench
