// An assimp module "of another build" for tests/test_assimp_module.cpp: it answers the entry
// point with an interface version one ahead (UNTANGLE_STALE_VERSION) or with a Mesh of another
// size (UNTANGLE_STALE_SIZES), and no functions. The library must refuse it before calling any.
#include "io/assimp_module.h"

extern "C" const untangle::assimp_module::Interface* untangle_assimp_interface() {
  using namespace untangle::assimp_module;
  static const Interface table = [] {
    Interface t = interface_of_this_build();
#ifdef UNTANGLE_STALE_VERSION
    t.version = kInterfaceVersion + 1;
#endif
#ifdef UNTANGLE_STALE_SIZES
    t.sizes.mesh += 8;
#endif
    return t;
  }();
  return &table;
}
