local m, b = 0, 0
for i = 1, 100000 do
  local n, l = i, 0
  while n ~= 1 do
    if n % 2 == 0 then n = n // 2 else n = 3 * n + 1 end
    l = l + 1
  end
  if l > m then m = l; b = i end
end
print(m, b)
