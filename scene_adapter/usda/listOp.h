// SPDX-License-Identifier: Apache-2.0
// Sdf list operations (references, inherits, apiSchemas, relationship targets, connections):
// an explicit list, or add / prepend / append / delete / reorder edits applied on top of the
// weaker opinions' result.
#pragma once

#include <algorithm>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace principled::usd {

/// The identity of a list item (two items with equal keys are the same item); other item types
/// give theirs by an overload found by argument-dependent lookup (layer.h).
inline const std::string& listOpKey(const std::string& s) { return s; }

enum class ListOpKind { Explicit, Add, Prepend, Append, Delete, Reorder };

template <class T>
struct ListOp {
    bool isExplicit = false;
    std::vector<T> explicitItems, added, prepended, appended, deleted, ordered;

    bool empty() const {
        return !isExplicit && added.empty() && prepended.empty() && appended.empty() &&
               deleted.empty() && ordered.empty();
    }

    /// Records one authored statement (a later statement of the same kind replaces it).
    void set(ListOpKind kind, std::vector<T> items) {
        switch (kind) {
            case ListOpKind::Explicit:
                *this = ListOp{};
                isExplicit = true;
                explicitItems = std::move(items);
                break;
            case ListOpKind::Add:
                added = std::move(items);
                break;
            case ListOpKind::Prepend:
                prepended = std::move(items);
                break;
            case ListOpKind::Append:
                appended = std::move(items);
                break;
            case ListOpKind::Delete:
                deleted = std::move(items);
                break;
            case ListOpKind::Reorder:
                ordered = std::move(items);
                break;
        }
    }

    /// Applies this (stronger) opinion on top of `list`, the result of the weaker ones, in Sdf's
    /// order: delete, add, prepend, append, reorder. Linear in the items (hash sets of their
    /// keys): a relationship may list a hundred thousand targets.
    void applyTo(std::vector<T>& list) const {
        using Keys = std::unordered_set<std::string>;
        auto keysOf = [](const std::vector<T>& items) {
            Keys k;
            k.reserve(items.size());
            for (const T& item : items) k.insert(listOpKey(item));
            return k;
        };
        auto removeAll = [&list](const Keys& keys) {
            if (keys.empty()) return;
            list.erase(std::remove_if(list.begin(), list.end(),
                                      [&keys](const T& item) { return keys.count(listOpKey(item)) > 0; }),
                       list.end());
        };
        if (isExplicit) {  // the first of repeated items stays
            list.clear();
            Keys seen;
            for (const T& item : explicitItems)
                if (seen.insert(listOpKey(item)).second) list.push_back(item);
            return;
        }
        removeAll(keysOf(deleted));
        if (!added.empty()) {
            Keys present = keysOf(list);
            for (const T& item : added)
                if (present.insert(listOpKey(item)).second) list.push_back(item);
        }
        if (!prepended.empty()) {  // the first of repeated items stays, in front
            std::vector<T> front;
            Keys seen;
            for (const T& item : prepended)
                if (seen.insert(listOpKey(item)).second) front.push_back(item);
            removeAll(seen);
            list.insert(list.begin(), front.begin(), front.end());
        }
        if (!appended.empty()) {  // each moves to the end in turn: the last of repeated items stays
            std::vector<T> back;
            Keys seen;
            for (auto it = appended.rbegin(); it != appended.rend(); ++it)
                if (seen.insert(listOpKey(*it)).second) back.push_back(*it);
            std::reverse(back.begin(), back.end());
            removeAll(seen);
            list.insert(list.end(), back.begin(), back.end());
        }
        if (!ordered.empty()) reorder(list);
    }

private:
    /// Sdf reorder: each named item moves, in the given order, together with the unnamed items
    /// that follow it; items before every named one stay in front.
    void reorder(std::vector<T>& list) const {
        std::vector<const T*> order;
        std::unordered_set<std::string> named;
        for (const T& item : ordered)
            if (named.insert(listOpKey(item)).second) order.push_back(&item);
        std::unordered_map<std::string, std::size_t> where;  // first position of each item
        for (std::size_t i = list.size(); i-- > 0;) where[listOpKey(list[i])] = i;
        std::vector<bool> taken(list.size(), false);
        std::vector<T> runs;
        for (const T* item : order) {
            auto it = where.find(listOpKey(*item));
            if (it == where.end()) continue;
            std::size_t i = it->second;
            do {
                runs.push_back(list[i]);
                taken[i] = true;
                ++i;
            } while (i < list.size() && !named.count(listOpKey(list[i])));
        }
        std::vector<T> result;
        result.reserve(list.size());
        for (std::size_t i = 0; i < list.size(); ++i)
            if (!taken[i]) result.push_back(list[i]);
        result.insert(result.end(), runs.begin(), runs.end());
        list = std::move(result);
    }
};

}  // namespace principled::usd
