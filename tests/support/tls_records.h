// What crossed the wire, read as TLS records (tests of the encrypted links).
#pragma once

#include <string>

namespace pathfarm::test {

// Splits a byte stream into TLS records (type, version, length): all_records is false when a
// header has an unknown type, version or an oversized length (the last record may be cut).
struct TlsRecordScan {
    bool all_records = false;
    int records = 0;
    int application_data = 0;  // content type 23
};
TlsRecordScan scan_tls_records(const std::string& bytes);

}  // namespace pathfarm::test
