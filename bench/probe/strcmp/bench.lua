local n = {"AB", "ABC", "B", "", "ab"}
local c, d = 0, 0
for i = 0, 999999 do
  local k = n[i % 5 + 1]
  if k == "ABC" then c = c + 1 end
  if k < "B" then d = d + 1 end
end
print(c, d)
