#pragma once
/// \file Id bookkeeping shared by the broad phases: boxes stored densely by id, a free list for reuse, the
/// checks that turn unknown or removed ids into cdkit::Error, and the public members every broad phase has in
/// common (SlotBroadPhase).

#include "cdkit/broadphase/box.hpp"

#include <vector>

namespace cdkit::detail {

template <class S> class ObjectSlots {
public:
    ObjectId insert(const BroadBox<S>& b) {
        check_box(b, "insert");
        ObjectId id;
        if (!free_.empty()) {
            id = free_.back();
            free_.pop_back();
            boxes_[id] = b;
            alive_[id] = 1;
        } else {
            id = static_cast<ObjectId>(boxes_.size());
            boxes_.push_back(b);
            alive_.push_back(1);
        }
        ++count_;
        return id;
    }
    void remove(ObjectId id) {
        check_id(id, "remove");
        alive_[id] = 0;
        free_.push_back(id);
        --count_;
    }
    void move(ObjectId id, const BroadBox<S>& b) {
        check_id(id, "move");
        check_box(b, "move");
        boxes_[id] = b;
    }
    void check_id(ObjectId id, const char* op) const {
        if (!contains(id))
            throw Error("<broadphase>", std::string(op) + " object " + std::to_string(id),
                        id < alive_.size() ? "already removed" : "unknown id");
    }
    [[nodiscard]] bool contains(ObjectId id) const noexcept { return id < alive_.size() && alive_[id]; }
    [[nodiscard]] std::size_t size() const noexcept { return count_; }
    /// One past the largest id ever handed out.
    [[nodiscard]] std::size_t capacity() const noexcept { return boxes_.size(); }
    [[nodiscard]] const BroadBox<S>& box(ObjectId id) const noexcept { return boxes_[id]; }
    [[nodiscard]] bool alive(ObjectId id) const noexcept { return alive_[id] != 0; }

private:
    std::vector<BroadBox<S>> boxes_;
    std::vector<unsigned char> alive_;
    std::vector<ObjectId> free_;
    std::size_t count_ = 0;
};

/// The members every broad phase shares, over ObjectSlots: insert / remove / move of a box by id, the const
/// look-ups, and find_pairs() through the derived class's for_each_pair (CRTP). Methods that keep more state
/// per object (sweep and prune, the tree) define their own insert / remove / move, which hide these.
template <class S, class Derived> class SlotBroadPhase {
public:
    using Scalar = S;

    /// Adds an object; throws cdkit::Error for a NaN/infinite box or min > max.
    ObjectId insert(const BroadBox<S>& b) { return slots_.insert(b); }
    /// Removes an object; throws cdkit::Error for an unknown or already removed id.
    void remove(ObjectId id) { slots_.remove(id); }
    /// Replaces an object's box; throws cdkit::Error for a bad id or box.
    void move(ObjectId id, const BroadBox<S>& b) { slots_.move(id, b); }
    [[nodiscard]] bool contains(ObjectId id) const noexcept { return slots_.contains(id); }
    [[nodiscard]] std::size_t size() const noexcept { return slots_.size(); }
    /// The box of a live object (precondition: contains(id)).
    [[nodiscard]] const BroadBox<S>& box(ObjectId id) const noexcept { return slots_.box(id); }
    /// The overlapping pairs, each once, a < b, in no particular order.
    [[nodiscard]] std::vector<ObjectPair> find_pairs() {
        std::vector<ObjectPair> out;
        static_cast<Derived*>(this)->for_each_pair([&](ObjectId a, ObjectId b) { out.push_back({a, b}); });
        return out;
    }

protected:
    ObjectSlots<S> slots_;
};

}  // namespace cdkit::detail
