#include "tests/support/tls_records.h"

namespace pathfarm::test {

TlsRecordScan scan_tls_records(const std::string& bytes) {
    TlsRecordScan scan;
    std::size_t at = 0;
    while (at + 5 <= bytes.size()) {
        const auto type = static_cast<unsigned char>(bytes[at]);
        const auto major = static_cast<unsigned char>(bytes[at + 1]);
        const auto minor = static_cast<unsigned char>(bytes[at + 2]);
        const std::size_t length = (std::size_t(static_cast<unsigned char>(bytes[at + 3])) << 8) |
                                   static_cast<unsigned char>(bytes[at + 4]);
        // 20 change_cipher_spec, 21 alert, 22 handshake, 23 application_data; TLS 1.3 writes
        // 0x0303 (0x0301 in the first ClientHello).
        if (type < 20 || type > 23 || major != 3 || (minor != 1 && minor != 3)) return scan;
        if (length > (1u << 14) + 256) return scan;
        at += 5 + length;
        ++scan.records;
        scan.application_data += type == 23;
    }
    scan.all_records = scan.records > 0;  // a record still in flight may be cut at the end
    return scan;
}

}  // namespace pathfarm::test
