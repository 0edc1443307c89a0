// OpenCL error codes by name, for one-line errors an operator can look up.
#pragma once

namespace pathfarm::tracer {

// "CL_OUT_OF_RESOURCES" for -5, and so on; "CL_ERROR(<code>)" for codes it does not know.
const char* cl_error_name(int code);

}  // namespace pathfarm::tracer
