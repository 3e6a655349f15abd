local a = "LABEL-0042-BATCH-7;OK"
local s, c = 0, 0
for i = 1, 200000 do
  local p = (i % #a) + 1
  s = (s + string.byte(string.sub(a, p, p)) * p) % 65521
  if string.sub(a, 1, 1) == "L" and string.sub(a, p, p) == "-" then c = c + 1 end
end
print(s, c)
