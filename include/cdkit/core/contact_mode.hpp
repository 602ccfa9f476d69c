#pragma once
/// \file How many contacts a query reports; shared by the discrete mesh queries and continuous collision, so it
/// lives below both.

namespace cdkit {

enum class ContactMode {
    first,  ///< stop at the first contact found (a witness; for continuous queries, the earliest in time)
    all,    ///< every contact (every intersecting triangle pair, every colliding feature pair)
};

}  // namespace cdkit
