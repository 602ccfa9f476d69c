#pragma once
/// \file Id bookkeeping shared by the broad phases: boxes stored densely by id, a free list for reuse, and the
/// checks that turn unknown or removed ids into cdkit::Error.

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

}  // namespace cdkit::detail
