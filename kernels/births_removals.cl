/* births_removals.cl: births and removals (after the form's lists file,
 * whose PF_ROW, PF_AT, PF_LIST_ROW and PF_ENTRY they use): while the lists
 * are valid they edit them in place (birth_linked, remove_linked);
 * otherwise they only write the state, and the next step rebuilds. */
/* One birth: writes particle `index` (the next step rebuilds the lists). */
__kernel void birth_one(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                        const uint index, const float4 x, const float4 v) {
  if (get_global_id(0) != 0) return;
  X[index] = x;
  V[index] = v;
  flags[index] = 0u;
  C[index] = 0.0f;
}

/* One birth while the lists are valid (one launch over n + 1 items, n
 * the count before the birth): item i < n lists the newcomer b = n if its
 * reference position XREF[i] is within PF_RL of b, the rule the lists were
 * built by (b's reference is where it is born): a pair left out can only
 * come within reach after drifts from the references of more than the skin
 * in all, which the rebuild test (each drift at most half the skin) rules
 * out. On GPUs it also takes a slot in b's list (list_count[b] is 0
 * beforehand); on CPU devices, where each pair is in one list, b's list
 * stays empty. Item n writes the newcomer (and, with PF_INNER, asks the
 * next step to prune). A full list raises the rebuild request the next
 * step reads. */
__kernel void birth_linked(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                           __global uint* list, __global uint* list_count, __global uint2* spans, __global float4* XREF,
                           __global uint* request, const uint request_next, const uint n, const float4 x,
                           const float4 v) {
  const uint i = get_global_id(0);
  if (i == n) {
    X[n] = x;
    V[n] = v;
    flags[n] = 0u;
    C[n] = 0.0f;
    XREF[n] = x;
#if PF_NEWTON
    spans[n] = (uint2)(0u, 0u); /* its list stays empty */
#endif
    /* the inner lists are packed by pair_forces' blocks, which the count sets */
    if (PF_INNER) atomic_or(&request[request_next], PF_REQUEST_PRUNE);
    return;
  }
  if (i > n) return;
  float4 d = XREF[i] - x;
  d.w = 0.0f;
  if (dot(d, d) >= PF_RL2) return;
  const uint mine = list_count[i];
#if PF_NEWTON
  /* each pair in one list: the newcomer's stays empty */
  if (mine < spans[i].y) {
    PF_AT(PF_LIST_ROW(list, spans, i), mine) = PF_ENTRY(n);
    list_count[i] = mine + 1u;
  } else {
    atomic_or(&request[request_next], PF_REQUEST_REBUILD);
  }
  return;
#endif
  const uint slot = atomic_inc(&list_count[n]);
  if (mine < PF_LIST_CAP && slot < PF_LIST_CAP) {
    PF_AT(PF_ROW(list, i), mine) = PF_ENTRY(n);
    list_count[i] = mine + 1u;
    PF_AT(PF_ROW(list, n), slot) = PF_ENTRY(i);
  } else {
    atomic_or(&request[request_next], PF_REQUEST_REBUILD);
  }
}

/* One removal while the lists are valid (one launch over n items, n the
 * count before it): particle `last` = n - 1 takes the place of `gone`. Item
 * `gone` copies the last particle's state and list (without `gone`); every
 * other item but `last` drops `gone` from its own list and renames `last`
 * to `gone`. The host then zeroes list_count[last]. */
__kernel void remove_linked(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                            __global uint* list, __global uint* list_count, __global uint2* spans,
                            __global float4* XREF, const uint n, const uint gone, __global uint* request,
                            const uint request_next) {
  const uint i = get_global_id(0);
  const uint last = n - 1u;
  if (PF_INNER && i == 0u) atomic_or(&request[request_next], PF_REQUEST_PRUNE); /* the inner lists name them too */
  if (i >= last) return;
  if (i == gone) {
    X[i] = X[last];
    V[i] = V[last];
    flags[i] = flags[last];
    C[i] = C[last];
    XREF[i] = XREF[last];
#if PF_NEWTON
    spans[i] = spans[last]; /* packed rows: the last particle's row becomes this one's, filtered in place */
#endif
    __global uint* row = PF_LIST_ROW(list, spans, i);
    __global const uint* from = PF_LIST_ROW(list, spans, last);
    const uint count = min(list_count[last], PF_LIST_CAP);
    uint kept = 0u;
    for (uint k = 0; k < count; ++k)
      if (PF_AT(from, k) != PF_ENTRY(gone)) {
        PF_AT(row, kept) = PF_AT(from, k); /* (PF_AT uses its arguments twice: no ++ in them) */
        ++kept;
      }
    list_count[i] = kept;
    return;
  }
  __global uint* row = PF_LIST_ROW(list, spans, i);
  uint count = min(list_count[i], PF_LIST_CAP);
  for (uint k = 0; k < count;) {
    if (PF_AT(row, k) == PF_ENTRY(gone)) {
      --count;
      PF_AT(row, k) = PF_AT(row, count);
    } else {
      if (PF_AT(row, k) == PF_ENTRY(last)) PF_AT(row, k) = PF_ENTRY(gone);
      ++k;
    }
  }
  list_count[i] = count;
}

/* One removal: particle `from` (the last) takes the place of `to`. */
__kernel void move_particle(__global float4* X, __global float4* V, __global uint* flags, __global float* C,
                            const uint from, const uint to) {
  if (get_global_id(0) != 0) return;
  X[to] = X[from];
  V[to] = V[from];
  flags[to] = flags[from];
  C[to] = C[from];
}

