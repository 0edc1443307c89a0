// What nearly every test file parses: GoogleTest, the standard library, fmt and GLM. It is
// precompiled once and every test target reuses it (tests/CMakeLists.txt), where each test file
// parsed it before: GoogleTest alone took 2-4 s of a test file's 9 s on the CI's machine. Only
// third-party and standard headers belong here, so that a test still has to include the
// project headers it uses (the layering check reads those includes).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
