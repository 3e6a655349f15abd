local a = "THE QUICK BROWN FOX JUMPS OVER THE LAZY DOG"
local c = 0
for i = 1, 200000 do
  local p = string.find(a, "LAZY", 1, true) or 0
  local b = string.sub(a, 1, 3) .. string.sub(a, -3)
  if p > 0 and #b == 6 then c = c + p end
  if string.byte(a, (i % 40) + 1) > 77 then c = c + 1 end
end
print(c)
